// The scenario model: what one YAML scenario describes, as plain structs (no YAML here; see
// config_io.h for the file format). A scenario = ground truth (camera, points, motion), a
// measurement source (oracle: exact projections plus noise; rendered: rendered, detected and
// matched frames), noise, the named method instances to run with their options
// (methods/registry.h), Monte Carlo trials and a seed, and optionally a published reference.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/config/fields.h"
#include "detect/rendered_source.h"
#include "diagnostics/source_diagnostics.h"
#include "methods/registry.h"
#include "metrics/tracking.h"
#include "sim/measurements.h"
#include "sim/scene.h"
#include "sim/synthetic.h"
#include "sim/target.h"

namespace calibench {

// Sizes beyond which a scenario is refused rather than run out of memory or time: a trial's
// frames (duration x sample rate, or x eval rate, or / noise hold for continuous sources) and the
// trials of one scenario.
constexpr double kMaxFramesPerTrial = 1e7;
constexpr long kMaxTrials = 1'000'000;
// An image larger than the renderer's bound (sim/render.h) is refused for every scenario: no
// camera calibrated here has one.
constexpr int kMaxImageSide = kMaxRenderSide;
constexpr double kMaxImagePixels = kMaxRenderPixels;
// The most feature points a scenario may have, however given (random, boards, AprilGrids).
constexpr int kMaxScenarioPoints = 100000;

constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

// Published figures to print beside ours (all optional: NaN / empty when absent).
struct Reference {
  std::string source;  // e.g. "thesis sim 7".
  std::string method;  // The instance it describes; empty: the scenario's first enabled one.
  double fku_px = kUnset, fkv_px = kUnset, phi_deg = kUnset, u0_px = kUnset, v0_px = kUnset;
  Eigen::Vector3d x_c = Eigen::Vector3d::Constant(kUnset);
  double theta_err_below = kUnset;  // "exact": the thesis reports ||theta~|| below this.
  bool Any() const;
};
bool operator==(const Reference& a, const Reference& b);

// Where a scenario sits in a sweep (config_io.h, `sweep:`). A sweep expands one scenario into the
// cartesian product of its axes; the points that differ only in `methods.*` fields form one
// measurement group: they share measurement_index, hence the trial seeds and the measurements (an
// instance whose options equal an earlier point's is not run again: run/trial.h).
struct SweepPoint {
  std::string sweep;           // The swept scenario's own name (= name when not swept).
  int index = 0;               // Position in the product (method axes vary fastest).
  int measurement_index = -1;  // Position among the measurement points; -1: not swept.
  std::string params;          // "field=value;field=value" (empty when not swept).
};
bool operator==(const SweepPoint& a, const SweepPoint& b);

// Estimates over time (a calibration that changes, dynamic-calibration.md): recorded for every
// method that reports them when the truth has changes, or when enabled.
struct TrackingConfig {
  bool enabled = false;         // Also without truth changes (e.g. the initial convergence).
  double report_rate_hz = 0.0;  // Report times: 0 = the source's frame times; else k / rate.
  // The per-time Monte Carlo bands (track_bands.csv) use at most this many report times per trial.
  int band_samples = 600;
  TrackingOptions metrics;  // Tolerances and the steady part of a segment.
  bool Check(std::string* why) const;
};

// report: {role}: the question of the report a scenario's rows answer (the report finds each
// sweep's role in schema.json instead of matching its name).
// noise (error against pixel noise), points (against the number of points), gain (against an
// adaptive gain), dynamic (a calibration that changes), rig (a camera rig's relative pose over
// time: rig.csv); none: no question of its own.
enum class ReportRole { kNone, kNoise, kPoints, kGain, kDynamic, kRig };
struct ReportConfig {
  ReportRole role = ReportRole::kNone;
};
// "none", "noise", "points", "gain", "dynamic", "rig".
const EnumNames<ReportRole>& ReportRoleNames();

enum class Detections { kOracle, kRendered };
enum class OutsideImage { kFail, kKeep };
// How the points were given: an explicit list, a preset, a random box, boards or AprilGrids.
enum class PointsForm { kList, kThesis, kRandom, kBoards, kAprilGrids };
const EnumNames<Detections>& DetectionsNames();
const EnumNames<OutsideImage>& OutsideImageNames();
const EnumNames<PointsForm>& PointsFormNames();
const char* ToString(Detections d);

// A board or grid with the rpy_deg it was given (the resolved YAML writes these, not angles
// recovered from the rotation, which may differ in the last digit and would not round-trip).
struct PlacedBoard {
  PlanarBoard board;
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
};
struct PlacedAprilGrid {
  AprilGrid grid;
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
};

// points: exactly one of {preset: thesis, count}, {list}, {random: {count, min, max}}, {boards},
// {aprilgrids}; `xyz` holds the resolved points in every form (random: drawn from the seed once the
// scenario is read).
struct PointsConfig {
  PointsForm form = PointsForm::kList;
  int count = 10;  // thesis / random: how many points.
  Eigen::Vector3d random_min = Eigen::Vector3d::Zero(), random_max = Eigen::Vector3d::Zero();
  std::vector<PlacedBoard> boards;          // The points are the rig's corners.
  std::vector<PlacedAprilGrid> aprilgrids;  // The tags' corners.
  std::vector<Eigen::Vector3d> xyz;

  std::vector<PlanarBoard> Boards() const;
  std::vector<AprilGrid> AprilGrids() const;
};
// The points, boards and grids (how they were written, a preset or a box, is not compared: the
// resolved YAML writes the points themselves).
bool operator==(const PointsConfig& a, const PointsConfig& b);

// A camera of a rig scenario (`rig.cameras[c]`; camera/rig.h states the rig conventions). Camera 0
// is the scenario's truth camera: its intrinsics and image size are truth.intrinsics and
// image_size (its entry gives neither) and its cam_from_rig is the identity; truth.R_C and x_C
// place the rig (= camera 0's frame) in the parent frame. Camera c >= 1 has its own intrinsics
// (any lens family), image size (default: the scenario's) and cam_from_rig, whose rotation is given
// as rpy_deg (FromRollPitchYawDeg, camera/pose.h) or as a 3x3 matrix R. Its pose in the parent
// frame is parent_from_cam_c = parent_from_cam_0 * cam_from_rig_c^-1.
struct RigCameraConfig {
  std::string name;  // Empty: "cam<c>".
  CameraIntrinsics intrinsics;
  bool intrinsics_given = false;          // The entry has `intrinsics` (camera 0's may not).
  int image_width = 0, image_height = 0;  // 0: the scenario's image_size.
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();  // cam_from_rig's rotation (from rpy_deg).
  bool rotation_as_matrix = false;                  // Given as `R` (written back so).
  Eigen::Vector3d t_m = Eigen::Vector3d::Zero();    // cam_from_rig's translation.
  Rigid3 CamFromRig() const { return {r, t_m}; }
};

// rig: {cameras: [...]}: the cameras of a rig scenario; empty: a single camera (the truth).
struct RigScenario {
  std::vector<RigCameraConfig> cameras;
  std::vector<std::string> marks;  // file:line:col of each camera (for messages).
  bool Any() const { return !cameras.empty(); }
};

struct ScenarioConfig {
  std::string name;
  std::string description;
  std::string source_file;  // The YAML file it came from (for messages).
  CalibrationCase calibration_case = CalibrationCase::kMovingCamera;
  double duration_s = 240.0;
  uint64_t seed = 1;
  int trials = 1;

  CameraSpec truth;                              // At t = 0.
  std::vector<CalibrationChange> truth_changes;  // truth.changes (sim/scene.h).
  std::vector<std::string> truth_change_marks;   // file:line:col of each (for messages).
  // truth.changes[i].camera of a rig scenario: the camera whose pose in the rig (and intrinsics)
  // the change moves; -1 (and absent entries): the whole rig (ChangeCamera).
  std::vector<int> truth_change_cameras;
  RigScenario rig;  // rig: the cameras of a rig; empty: one camera.
  TrackingConfig tracking;
  int image_width = 640, image_height = 480;  // For zhang's initialisation.
  PointsConfig points;
  std::optional<ThesisMotion> motion_preset;  // motion.preset; none: the twist as written.
  TwistProfile motion;                        // Frame already resolved from the case.
  // motion.random_phase: each trial's twist starts at its own phase of the profile's period
  // (drawn from the trial seed), so trials see different views, not only different noise.
  bool motion_random_phase = false;

  // oracle: exact projections + noise (OracleSource); rendered: frames rendered at
  // measurements.sample_rate_hz, detected and matched (RenderedSource; needs aprilgrids).
  Detections detections = Detections::kOracle;
  // oracle: a projection outside image_size is an error (fail: the trial fails, naming the point)
  // or measured anyway (keep: the thesis's model, with no image bound).
  OutsideImage outside_image = OutsideImage::kFail;
  OracleOptions measurements;       // sample rate, eval rate and noise (noise: oracle only).
  RenderedSourceOptions rendering;  // rendered: frame_rate_hz = measurements.sample_rate_hz.
  DiagnosticsOptions diagnostics;   // Study-only decorators of the source (none by default).

  // The method instances in row order. The default is one instance per registered type, named after
  // it, enabled as the type says (the map form of `methods:`, registry.h).
  std::vector<MethodInstance> methods = DefaultMethods();
  Reference reference;
  SweepPoint sweep_point;
  ReportConfig report;

  // paired_sweep: every sweep point runs the same trials (seeds) as the unswept scenario, so
  // its rows pair trial by trial with the other points' (a diagnostic that changes one thing at a
  // time); false: each measurement point draws its own trials.
  bool paired_sweep = false;

  // The seed of Monte Carlo trial `trial`: TrialSeed(seed, trial), or for a sweep point
  // TrialSeed(PointSeed(seed, measurement_index), trial), so the method-only points of a group
  // see the same draws and every measurement point its own (all TrialSeed(seed, trial) when
  // paired_sweep).
  uint64_t TrialSeedOf(int trial) const;
  // The ground truth scene (motion integrated over duration_s, changes included).
  // The scene of a trial (of any trial when the motion has no random phase: then trial_seed is
  // not used).
  SceneTruth MakeScene(uint64_t trial_seed = 0) const;
  // Whether the trials record estimates over time (truth changes, or tracking.enabled).
  bool Tracks() const { return tracking.enabled || !truth_changes.empty(); }

  // Rigs (composition of single cameras: each camera of the rig is measured and estimated on its
  // own, as the scenario's single camera is).
  int NumCameras() const { return rig.Any() ? static_cast<int>(rig.cameras.size()) : 1; }
  // The camera truth change i moves: -1 the whole rig (or the single camera), else its index.
  int ChangeCamera(size_t i) const {
    return i < truth_change_cameras.size() ? truth_change_cameras[i] : -1;
  }
  std::string CameraName(int c) const;  // rig.cameras[c].name, or "cam<c>".
  // Camera c of the rig as a single-camera scenario (truth at t = 0, intrinsics, image size, and
  // the changes that move it: the whole rig's and its own; tracking enabled when the rig tracks),
  // for its rows and metrics; its scene is MakeCameraScene(c), not its MakeScene. Camera 0 without
  // changes of its own, of a rig moved by a change of the whole rig, and any camera of a scenario
  // without `rig`, is the scenario itself in all a trial reads.
  ScenarioConfig CameraScenario(int c) const;
  // Camera c's scene: MakeScene with camera c's intrinsics, rig_from_cam and own changes
  // (SceneTruth::rig_from_cam, rig_changes). MakeCameraScene(0) of a camera without changes of its
  // own is MakeScene.
  SceneTruth MakeCameraScene(int c, uint64_t trial_seed = 0) const;
  // The seed of camera c's measurement noise in a trial: camera 0's is the trial seed (a rig's
  // camera 0 sees the draws of the single-camera scenario), camera c's is drawn from (trial seed,
  // c).
  static uint64_t CameraSeed(uint64_t trial_seed, int c);
  // The rig's checks (ScenarioConfig::Check): at least 2 cameras, camera 0 the truth at the
  // identity, proper rotations, valid intrinsics and image sizes, cameras apart, every point in
  // front of every camera at t = 0 and inside its image (outside_image: fail; keep: at least one),
  // change cameras that exist. False with the camera's index (-1: not one camera's) or the change's
  // (*change, -1: none), the field and the reason.
  bool CheckRig(int* camera, int* change, std::string* field, std::string* why) const;
  // The planar boards (PlanarBoard or AprilGrid) in point order; empty for other point sets.
  std::vector<BoardLayout> BoardLayouts() const;
  // The instance named `instance`, or null.
  const MethodInstance* FindMethod(const std::string& instance) const;
  MethodInstance* FindMethod(const std::string& instance);
  // The enabled instances, in row order.
  std::vector<const MethodInstance*> EnabledMethods() const;
  // One instance per registered type, named after it (the default methods of a scenario).
  static std::vector<MethodInstance> DefaultMethods();
  // The rendering options with the scenario's frame rate and image size filled in.
  RenderedSourceOptions RenderingOptions() const;
  // The oracle options, with the image bound in force when outside_image is fail.
  OracleOptions OracleSourceOptions() const;
  bool Check(std::string* why) const;
};
// Every declared field equal (the methods by their options' key): what a configuration must read
// back to.
bool operator==(const ScenarioConfig& a, const ScenarioConfig& b);

// The declarations of the scenario format (scenario_fields.cc; the measurement sources' in
// source_fields.cc).
void Visit(FieldVisitor& v, ScenarioConfig& s);
void Visit(FieldVisitor& v, CameraSpec& c);
void Visit(FieldVisitor& v, CameraIntrinsics& k);
void Visit(FieldVisitor& v, CalibrationChange& c);
void Visit(FieldVisitor& v, RigCameraConfig& c);
void Visit(FieldVisitor& v, TrackingConfig& t);
void Visit(FieldVisitor& v, Reference& r);
void Visit(FieldVisitor& v, ReportConfig& r);
void Visit(FieldVisitor& v, SweepPoint& p);
void Visit(FieldVisitor& v, NoiseOptions& n);
void Visit(FieldVisitor& v, RenderedSourceOptions& o);
void Visit(FieldVisitor& v, DiagnosticsOptions& d);
void Visit(FieldVisitor& v, AprilTagOptions& a);
void Visit(FieldVisitor& v, PlacedBoard& b);
void Visit(FieldVisitor& v, PlacedAprilGrid& g);
// The keys of `points:` (its grammar is read by hand: config_io.cc).
void Visit(FieldVisitor& v, PointsConfig& p);
// The keys of `points.random`.
void VisitRandomBox(FieldVisitor& v, PointsConfig& p);
// The top-level keys that a sweep axis may start with.
std::vector<std::string> SweepableKeys();

}  // namespace calibench
