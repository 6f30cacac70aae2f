// The method interface: one estimator as the harness runs it on one trial's measurements.
//
// A method type (adaptive, dlt, zhang, zhang_handeye, ceres, ...) is a class implementing Method,
// listed once in methods/registry.cc; a scenario holds named instances of types (registry.h). For
// each trial the harness builds a MethodInput, calls Run() on every enabled instance, and hands
// the result to the metrics (metrics/metrics.h). A method sees the measurements, never the truth:
//
//   MethodInput   the measurement source (continuous, or frames held between samples), the same
//                 frames read once as views of the parent frame, the image size, the planar boards
//                 of the point set, and the known motion of the points frame (the body poses the
//                 thesis assumes known). Prerequisite(name) runs another instance of the scenario
//                 (or a type's default, by type name) once per trial and returns its result: how
//                 ceres starts from dlt or zhang. Cache() shares intermediate work between the
//                 methods of a trial (zhang and zhang_handeye share one calibrateCamera).
//   MethodResult  status, message, iterations and wall time (util/status.h), the estimate
//                 (camera/estimate.h), the data it used and the values of its declared outputs.
//   EstimateSink  estimates over time, as the method produces them, and named series of its own
//                 state (the harness turns them into ||theta~||(t), convergence times, curves).
//
// Options: each type declares its options once, in one function, VisitOptions(): per option its
// key, unit and one-line doc (OptionSpec) and the member. It is called with a visitor that reads
// them (the config I/O, from YAML: methods never see YAML), writes them (the resolved
// configuration), turns them into text (options.h: the key that decides whether two sweep points
// may share a result) or documents them (`calibench config-reference` and `calibench methods`,
// bench/config/config_reference.h). Check() validates them after reading.
//
// Outputs: the figures a type reports beyond its estimate (the adaptive estimator's
// persistent-excitation index), each declared once in Outputs() (OutputSpec: name, unit, label,
// doc, how summary.csv summarises it). The harness writes exactly the declared outputs of the
// registered types: their runs.csv columns, their quantities in schema.json and their summary.csv
// rows (bench/run/run_row.h). A result sets only what its type declares (CheckOutputs,
// registry.h); an output it leaves unset is NaN in its row.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/estimate.h"
#include "camera/parametrisation.h"
#include "camera/view.h"
#include "sim/measurements.h"
#include "sim/scene.h"
#include "sim/target.h"
#include "util/status.h"

namespace calibench {

// One option's declaration, given once at its VisitOptions call: `key` is its name in configs,
// `unit` its unit ("" when none; "s", "px", "deg", ... as the key's suffix says), `doc` one line
// saying what it does (the reference, docs/configuration.md, and `calibench methods` print both).
struct OptionSpec {
  const char* key;
  const char* unit = "";
  const char* doc = "";
};

// How summary.csv summarises a method output over the ok trials of a (scenario, method).
enum class OutputSummary {
  kNone,        // Not summarised: runs.csv only.
  kStatistics,  // n_used, median, mean, std, percentiles of the values and of |value|.
};

// One output's declaration (Method::Outputs): `name` is its runs.csv column and follows the
// naming rule of metrics/metric_table.h (lower-case words, the unit last: _px, _s, ...; none when
// dimensionless), `unit` its unit ("" when none), `label` a short name (tables, plots), `doc` one
// line (schema.json, docs/outputs.md), `summary` how summary.csv summarises it.
struct OutputSpec {
  const char* name;
  const char* unit = "";
  const char* label = "";
  const char* doc = "";
  OutputSummary summary = OutputSummary::kNone;
};

// The windup law of an estimator whose gain decays as 1/t (the Clemson adaptive-calibration
// thesis's): after a step change of the truth at t0 its error decays as (t0 / t)^a, so it is back
// within tol after (t0 / a) ln(e0 / tol), e0 the step. `exponent_option` names the option holding
// a; the law holds for the instances whose options `only_when_zero` are all 0 (they change how the
// gain decays). The report compares the measured re-convergence times with it (schema.json).
struct WindupLaw {
  const char* exponent_option;
  std::vector<const char*> only_when_zero;
};

// Reads or writes one option. An implementation that reads leaves *value untouched when the key
// is absent and reports a bad value itself (naming file, line and field); one that writes only
// reads *value.
class OptionVisitor {
 public:
  virtual ~OptionVisitor() = default;
  virtual void Field(const OptionSpec& spec, double* value) = 0;
  virtual void Field(const OptionSpec& spec, int* value) = 0;
  virtual void Field(const OptionSpec& spec, long* value) = 0;
  virtual void Field(const OptionSpec& spec, bool* value) = 0;
  // A string; when `choices` is not empty it must be one of them.
  virtual void Field(const OptionSpec& spec, std::string* value,
                     const std::vector<std::string>& choices) = 0;
  virtual void Field(const OptionSpec& spec, LensModel* value) = 0;
  virtual void Field(const OptionSpec& spec, CameraSpec* value) = 0;  // intrinsics, R_C, x_C, ...
  // Seconds, or the word `all` (infinity): a window length.
  virtual void FieldOrAll(const OptionSpec& spec, double* seconds) = 0;
};

// An option over a closed set (an enum class): `names` spells each value in the configs, in
// declaration order. The visitor sees a string with its choices; the value read is mapped back.
template <typename E>
void EnumOption(OptionVisitor* v, const OptionSpec& spec, E* value,
                const std::vector<std::pair<E, const char*>>& names) {
  std::string name = names.front().second;
  std::vector<std::string> choices;
  for (const auto& [e, n] : names) {
    choices.push_back(n);
    if (e == *value) name = n;
  }
  v->Field(spec, &name, choices);
  for (const auto& [e, n] : names) {
    if (name == n) *value = e;
  }
}

// The frames of a trial's source as views of the parent frame (what batch methods pool).
struct FrameSet {
  std::vector<View> views;                  // Per frame: x_bar (points in P) and measured pixels.
  std::vector<double> times_s;              // Per frame.
  std::vector<std::vector<int>> point_ids;  // Per frame: the scene point of each entry.
};
FrameSet ReadFrames(const MeasurementSource& source);
// Frames with at least one observation, and observations, of `frames`.
void CountDataUsed(const FrameSet& frames, long* frames_used, long* observations_used);

// The per-view problem of a planar-target calibration (zhang): the views it used, with the board
// points in the board frame, each view's solved board pose and where that board was in the parent
// frame (known body motion and board placement). A method that re-solves exactly those views
// (ceres with `views: init`) starts from it.
struct PerViewSolution {
  std::vector<View> views;                // Board-local points and measured pixels.
  std::vector<Rigid3> cam_from_board;     // Per view, as solved.
  std::vector<Rigid3> parent_from_board;  // Per view, known.
};

struct MethodResult : MethodSummary {
  CameraEstimate estimate;
  // The values of the method's declared outputs (Method::Outputs), by name; one it does not set
  // is NaN in runs.csv. Set them with SetOutput.
  std::map<std::string, double> outputs;
  // The data the estimate used (runs.csv n_frames_used, n_obs_used): frames with at least one
  // observation, and corner observations. -1: every frame of the input (the harness counts them).
  long frames_used = -1, observations_used = -1;
  // Set by methods that solve per-view problems (see PerViewSolution); null otherwise.
  std::shared_ptr<const PerViewSolution> per_view;

  void SetOutput(const OutputSpec& spec, double value) { outputs[spec.name] = value; }
};

// The series name of the linear form theta_hat (EstimateSink::OnSeries).
inline constexpr const char* kThetaSeries = "theta";

// Estimates over time, in the order the method produces them.
class EstimateSink {
 public:
  virtual ~EstimateSink() = default;
  // A sample at time t of a named series of the method's own state. The harness knows
  // kThetaSeries (the linear form theta_hat of camera/projection_matrix.h, 16 values: the adaptive
  // estimator's state, at t = 0 and after every accepted integrator step) and ignores others.
  virtual void OnSeries(double t_s, const std::string& series, const Eigen::VectorXd& value) = 0;
  // The method's estimate from time t on (until its next one): online methods at their report
  // times (MethodInput::report_times_s, a batch solve, a filter update). Static methods emit none.
  virtual void OnEstimate(double t_s, const CameraEstimate& estimate) = 0;
};

// Work shared by the methods of one trial, keyed by text that names everything it depends on
// besides the trial's measurements. Not thread-safe: a trial runs its methods one after another.
class TrialCache {
 public:
  template <typename T>
  const T& Get(const std::string& key, const std::function<T()>& make) {
    auto it = entries_.find(key);
    if (it == entries_.end()) it = entries_.emplace(key, std::make_shared<T>(make())).first;
    return *static_cast<const T*>(it->second.get());
  }

 private:
  std::map<std::string, std::shared_ptr<void>> entries_;
};

struct MethodInput {
  const MeasurementSource* source = nullptr;
  // Frames with time_s in [window_from_s, window_to_s] are what Frames() holds (a batch method in
  // online mode solves on a window of the trial: methods/online.h); the whole trial by default.
  double window_from_s = -std::numeric_limits<double>::infinity();
  double window_to_s = std::numeric_limits<double>::infinity();
  // When estimates over time are wanted (a calibration that changes): the times at which a method
  // that follows the data (adaptive, a filter) reports its state. Empty: report nothing.
  std::vector<double> report_times_s;
  int image_width = 0, image_height = 0;
  // The lens family of the scenario's camera (its truth's), as a user knows the lens on the
  // camera: methods that assume a pinhole projection refuse the omnidirectional families
  // (RefuseWideLens).
  LensFamily lens = LensFamily::kRadTan;
  std::vector<BoardLayout> boards;  // Planar boards of the point set, in point order; may be empty.
  // Where the points frame (body for a fixed camera, world for a moving one) is in the parent
  // frame at time t: known, as the thesis assumes the body poses known (sim/scene.h).
  std::function<Rigid3(double t_s)> parent_from_points;
  // The result of the scenario's instance `name`, or of the default instance of the type `name`
  // when the scenario has no instance of that name, on `input` (this trial, or a window of it);
  // run at most once per trial and window.
  std::function<const MethodResult&(const std::string& name, const MethodInput& input)>
      prerequisite;
  TrialCache* cache = nullptr;
  // A window's frames (Window() selects them once; null for the whole trial, read from the cache).
  std::shared_ptr<const FrameSet> window_frames;
  // A rig scenario (camera/rig.h): every camera's input of this trial, camera 0 first, and which
  // of them this one is; empty for a single camera. Methods that estimate the rig jointly
  // (ekf_rig) read all cameras' frames and prerequisites through them; the others ignore them.
  std::vector<const MethodInput*> rig_inputs;
  int rig_camera = 0;

  // The source's frames inside the window, read once per trial and window.
  const FrameSet& Frames() const;
  const MethodResult& Prerequisite(const std::string& name) const {
    return prerequisite(name, *this);
  }
  // This input restricted to the frames of [from_s, to_s] (online mode), without report times.
  MethodInput Window(double from_s, double to_s) const;
  // "" for the whole trial, else the window's bounds: part of every cache key of a windowed input.
  std::string WindowKey() const;
};

// For a method that assumes a pinhole projection (dlt, adaptive, ekf, zhang with a radtan or
// equidistant model): true when input.lens is unified, eucm or double-sphere (rays at and past
// 90 deg from the axis, which no pinhole projection images), with *result failed and the reason
// naming `method` and the lens. The sweep records the failed row and goes on.
bool RefuseWideLens(const MethodInput& input, const std::string& method, MethodResult* result);

class Method {
 public:
  virtual ~Method() = default;
  virtual std::unique_ptr<Method> Clone() const = 0;
  // Reads or writes every option (see the header comment). Writers only read the fields.
  virtual void VisitOptions(OptionVisitor* visitor) = 0;
  virtual bool Check(std::string* why) const = 0;
  // Names the instances or types Run() asks input.prerequisite for (their results are part of what
  // its result depends on).
  virtual std::vector<std::string> Prerequisites() const { return {}; }
  // The parametrisation (lens model, skew, one shared pose) whose Cramer-Rao bound the method's
  // rows carry; none by default.
  virtual std::optional<Parametrisation> BoundParametrisation() const { return std::nullopt; }
  // The figures its results report beyond the estimate (see the header comment); none by default.
  virtual std::vector<OutputSpec> Outputs() const { return {}; }
  // The windup law its error follows after a change of the truth, if it has one.
  virtual std::optional<WindupLaw> Windup() const { return std::nullopt; }
  // Never throws for bad data: a failed result with a message instead. `sink` may be null.
  virtual MethodResult Run(const MethodInput& input, EstimateSink* sink) const = 0;
};

// VisitOptions on a method that is only read (a writer or the text key).
inline void VisitOptionsReadOnly(const Method& method, OptionVisitor* visitor) {
  const_cast<Method&>(method).VisitOptions(visitor);  // NOLINT: writers do not modify.
}

}  // namespace calibench
