#include "bench/run/trial.h"

#include <chrono>
#include <cmath>
#include <deque>
#include <memory>

#include "methods/options.h"
#include "methods/registry.h"
#include "util/format.h"

namespace calibench {
namespace {

// The trial's measurement source; *base gets the seed and the detection figures. Null (and *why)
// when the measurements cannot be produced.
std::unique_ptr<MeasurementSource> MakeSource(const ScenarioConfig& s, const SceneTruth& scene,
                                              RunRow* base, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<MeasurementSource> source;
  if (s.detections == Detections::kRendered) {
    auto rendered =
        RenderedSource::Create(scene, s.points.AprilGrids(), s.RenderingOptions(), base->seed, why);
    if (rendered) {
      const DetectionStats& stats = rendered->stats();
      base->detect_rate = stats.DetectionRate();
      base->corner_rms_px = stats.rms_px;
      base->corner_radial_bias_px = stats.bias_radial_px;
      base->corner_crlb_px = stats.crlb_rms_px;
      base->frames_no_detection = stats.frames_without_detections;
    }
    source = std::move(rendered);
  } else {
    source = OracleSource::Create(scene, s.OracleSourceOptions(), base->seed, why);
  }
  if (source && s.diagnostics.Active()) {
    source = ApplyDiagnostics(std::move(source), scene, s.points.AprilGrids(), s.diagnostics, why);
    if (!source && why) *why = "diagnostics: " + *why;
  }
  base->measure_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return source;
}

RunRow BaseRow(const ScenarioConfig& s, int trial) {
  RunRow base;
  base.scenario = s.name;
  base.sweep = s.sweep_point.sweep.empty() ? s.name : s.sweep_point.sweep;
  base.point = s.sweep_point.index;
  base.params = s.sweep_point.params;
  base.n_points = static_cast<int>(s.points.xyz.size());
  base.trial = trial;
  base.seed = s.TrialSeedOf(trial);
  return base;
}

// Failed rows for every enabled instance of `s`.
void AppendFailed(const ScenarioConfig& s, const RunRow& base, const std::string& message,
                  std::vector<RunRow>* rows) {
  for (const MethodInstance* m : s.EnabledMethods()) {
    RunRow failed = base;
    failed.method = m->name;
    failed.status = "failed";
    failed.message = message;
    rows->push_back(failed);
  }
}

// The instance `name` of `s`, or the default instance of the type `name` (kept in *defaults).
const MethodInstance* Resolve(const ScenarioConfig& s, const std::string& name,
                              std::deque<MethodInstance>* defaults) {
  if (const MethodInstance* m = s.FindMethod(name)) return m;
  for (const MethodInstance& d : *defaults) {
    if (d.name == name) return &d;
  }
  defaults->push_back(MethodInstance::OfType(name, name));
  return defaults->back().method ? &defaults->back() : nullptr;
}

std::string KeyOf(const ScenarioConfig& s, const MethodInstance& instance, int depth,
                  std::deque<MethodInstance>* defaults) {
  std::string key = instance.type + "{" + OptionsKey(*instance.method) +
                    "}tol=" + FormatNumber(instance.convergence_tol, 17);
  if (depth > 16) return key + "<cycle>";  // Refused by ScenarioConfig::Check; never run.
  for (const std::string& used : instance.method->Prerequisites()) {
    const MethodInstance* p = Resolve(s, used, defaults);
    key += "<" + used + ":" + (p ? KeyOf(s, *p, depth + 1, defaults) : "?") + ">";
  }
  return key;
}

// A method's result with what the metrics need of its trajectory.
struct Outcome {
  MethodResult result;
  int trajectory_samples = 0;
  double converge_time_s = kNoValue;
  std::vector<std::pair<double, double>> curve;
  std::vector<TrackPoint> track;  // Tracking scenarios: at the report times.
  std::vector<EventMetrics> events;
};

// What a method reports over time: theta_hat into ||theta~||(t), estimates into its trajectory.
class TrackSink final : public EstimateSink {
 public:
  TrackSink(ThetaTrack* theta, EstimateTrack* estimates) : theta_(theta), estimates_(estimates) {}
  void OnSeries(double t_s, const std::string& series, const Eigen::VectorXd& value) override {
    if (series != kThetaSeries || value.size() != 16) return;
    theta_->Add(t_s, value);
    ++theta_samples;
  }
  void OnEstimate(double t_s, const CameraEstimate& estimate) override {
    if (estimates_ != nullptr) estimates_->Add(t_s, estimate);
  }
  int theta_samples = 0;

 private:
  ThetaTrack* theta_;
  EstimateTrack* estimates_;
};

// Runs the instances of one scenario of the group on the trial's measurements.
class ScenarioTrial {
 public:
  ScenarioTrial(const ScenarioConfig& s, const SceneTruth& scene, const MeasurementSource& source,
                TrialCache* cache, const GroupTrialOptions& options)
      : s_(s), scene_(scene), cache_(cache), options_(options) {
    input_.source = &source;
    input_.image_width = s.image_width;
    input_.image_height = s.image_height;
    input_.lens = s.truth.intrinsics.family;
    input_.boards = s.BoardLayouts();
    input_.parent_from_points = [&scene](double t) { return scene.ParentFromPoints(t); };
    input_.cache = cache;
    input_.prerequisite = [this](const std::string& name,
                                 const MethodInput& on) -> const MethodResult& {
      return OutcomeOf(*Resolve(s_, name, &defaults_), on).result;
    };
    if (s.Tracks()) {
      input_.report_times_s = s.tracking.report_rate_hz > 0
                                  ? FrameTimes(s.tracking.report_rate_hz, source.Duration())
                                  : input_.Frames().times_s;
      for (const CalibrationChange& c : s.truth_changes) event_times_.push_back(c.from_s);
    }
  }

  std::string Key(const MethodInstance& instance) { return KeyOf(s_, instance, 0, &defaults_); }

  const Outcome& OutcomeOf(const MethodInstance& instance) { return OutcomeOf(instance, input_); }
  const Outcome& OutcomeOf(const MethodInstance& instance, const MethodInput& input) {
    return cache_->Get<Outcome>("outcome:" + Key(instance) + input.WindowKey(), [&] {
      ThetaTrack::Options track_options;
      track_options.tolerance = instance.convergence_tol;
      track_options.record_curve = options_.record_curve;
      track_options.max_samples = options_.curve_samples;
      ThetaTrack track(s_.truth, track_options);
      EstimateTrack estimates;
      const bool tracks = !input.report_times_s.empty();
      TrackSink sink(&track, tracks ? &estimates : nullptr);
      Outcome outcome;
      outcome.result = instance.method->Run(input, &sink);
      outcome.trajectory_samples = sink.theta_samples;
      outcome.converge_time_s = track.ConvergeTimeS();
      outcome.curve = track.Curve();
      if (tracks && !estimates.empty()) {
        outcome.track =
            estimates.Sample(input.report_times_s, [this](double t) { return scene_.CameraAt(t); });
        outcome.events = EvaluateEvents(outcome.track, event_times_, input.source->Duration(),
                                        s_.tracking.metrics);
      }
      return outcome;
    });
  }

  RunRow Row(const MethodInstance& instance, RunRow row, ScenarioShared* shared) {
    row.method = instance.name;
    const Outcome& outcome = OutcomeOf(instance);
    const MethodResult& r = outcome.result;
    row.wall_ms = r.wall_ms;
    std::string undeclared;
    if (!CheckOutputs(*instance.method, r, &undeclared)) {  // A programmer error: a failed row.
      row.status = ToString(MethodStatus::kFailed);
      row.message = undeclared;
      return row;
    }
    row.status = ToString(r.status);
    row.steps = r.iterations;
    const CameraEstimate& e = r.estimate;
    const EstimateMetrics m = EvaluateEstimate(r.status, e, s_.truth, input_.Frames().views);
    row.message =
        m.warning.empty() ? r.message : m.warning + (r.message.empty() ? "" : "; " + r.message);
    if (e.has_camera) {
      const CameraIntrinsics& k = e.intrinsics;
      row.fku_px = k.fku_px;
      row.fkv_px = k.fkv_px;
      row.phi_deg = k.phi_deg;
      row.u0_px = k.u0_px;
      row.v0_px = k.v0_px;
      const Eigen::Vector3d rpy = RollPitchYawOfRc(e.parent_from_cam.rotation, e.improper);
      row.roll_deg = rpy[0];
      row.pitch_deg = rpy[1];
      row.yaw_deg = rpy[2];
      row.xc_x_m = e.parent_from_cam.translation[0];
      row.xc_y_m = e.parent_from_cam.translation[1];
      row.xc_z_m = e.parent_from_cam.translation[2];
      row.err_fku_px = m.errors.fku_px;
      row.err_fkv_px = m.errors.fkv_px;
      row.err_phi_deg = m.errors.phi_deg;
      row.err_u0_px = m.errors.u0_px;
      row.err_v0_px = m.errors.v0_px;
      row.rot_err_deg = m.errors.rotation_deg;
      row.xc_err_m = m.errors.position_m;
      row.err_roll_deg = m.errors.roll_deg;
      row.err_pitch_deg = m.errors.pitch_deg;
      row.err_yaw_deg = m.errors.yaw_deg;
      row.ortho_defect = e.orthogonality_defect;
      row.improper = e.improper ? 1 : 0;
    }
    row.theta_err_norm = m.theta_err_norm;
    row.rms_reproj_px = m.rms_reproj_px;
    if (r.IsUsable() && outcome.trajectory_samples > 0)
      row.converge_time_s = outcome.converge_time_s;
    row.method_outputs = r.outputs;
    row.n_frames_used = r.frames_used;
    row.n_obs_used = r.observations_used;
    if (r.frames_used < 0 && r.IsUsable()) {  // A failed row used nothing: it keeps -1.
      CountDataUsed(input_.Frames(), &row.n_frames_used, &row.n_obs_used);
    }
    const double deg = 180.0 / M_PI;
    row.std_fku_px = e.intrinsics_std[0];
    row.std_fkv_px = e.intrinsics_std[1];
    row.std_phi_deg = e.intrinsics_std[2] * deg;
    row.std_u0_px = e.intrinsics_std[3];
    row.std_v0_px = e.intrinsics_std[4];
    FillCrlb(instance, shared, &row);
    row.curve = outcome.curve;
    row.track = outcome.track;
    row.events = outcome.events;
    row.frames = input_.source->NumFrames();
    return row;
  }

 private:
  // The Cramer-Rao bound of the instance's parametrisation, for scenarios with white pixel noise
  // only (what it models); computed once per scenario and parametrisation. Rendered detections:
  // the bound of white noise of the detector's measured error per axis (corner_rms_px / sqrt 2)
  // on the observations it detected in this trial: equal corner error and equal data, the
  // reference a rendered row's error compares to (RMSE / CRLB).
  void FillCrlb(const MethodInstance& instance, ScenarioShared* shared, RunRow* row) {
    const std::optional<Parametrisation> model = instance.method->BoundParametrisation();
    const NoiseOptions& noise = s_.measurements.noise;
    const bool rendered = s_.detections == Detections::kRendered;
    const double sigma_px = rendered ? row->corner_rms_px / std::sqrt(2.0) : noise.pixel_sigma_px;
    if (!model || !(sigma_px > 0) || noise.point_sigma_m > 0) return;
    const std::string key = std::string(ToString(model->model)) +
                            (model->estimate_skew ? "+skew" : "") +
                            (model->autodiff ? "+autodiff" : "");
    CrlbStd bound;
    auto compute = [&] { return CramerRaoStd(input_.Frames().views, s_.truth, *model, sigma_px); };
    // Else every trial has its own views (and a rendered one its own detections and error).
    if (shared != nullptr && !s_.motion_random_phase && !rendered) {
      std::lock_guard<std::mutex> lock(shared->mutex);
      auto it = shared->crlb.find(key);
      if (it == shared->crlb.end()) it = shared->crlb.emplace(key, compute()).first;
      bound = it->second;
    } else {
      bound = compute();
    }
    if (!bound.valid) return;
    row->crlb_fku_px = bound.std_px[0];
    row->crlb_fkv_px = bound.std_px[1];
    row->crlb_phi_deg = bound.std_px[2];
    row->crlb_u0_px = bound.std_px[3];
    row->crlb_v0_px = bound.std_px[4];
  }

  const ScenarioConfig& s_;
  const SceneTruth& scene_;
  std::vector<double> event_times_;  // The truth changes' start times.
  TrialCache* cache_;
  GroupTrialOptions options_;
  MethodInput input_;
  std::deque<MethodInstance> defaults_;  // Default instances asked for by type name.
};

// Rows copied from an earlier point of the group, relabelled as `base`'s (not run again).
RunRow CopyOf(RunRow row, const RunRow& base) {
  row.scenario = base.scenario;
  row.sweep = base.sweep;
  row.point = base.point;
  row.params = base.params;
  row.n_points = base.n_points;
  row.wall_ms = 0.0;
  row.measure_ms = base.measure_ms;
  row.reused = true;
  return row;
}

std::vector<RunRow> RunGroupTrialUnguarded(const std::vector<const ScenarioConfig*>& group,
                                           int trial, ScenarioShared* shared,
                                           const GroupTrialOptions& options) {
  const ScenarioConfig& first = *group.front();
  RunRow base = BaseRow(first, trial);
  std::string why;
  const SceneTruth scene = first.MakeScene(first.TrialSeedOf(trial));
  const std::unique_ptr<MeasurementSource> source = MakeSource(first, scene, &base, &why);
  TrialCache cache;  // Shared by the group: same measurements.
  std::vector<RunRow> rows;
  struct Done {
    std::string name, key;
    size_t row;
  };
  std::vector<Done> done;  // Rows computed so far in this group, for copies.
  for (size_t j = 0; j < group.size(); ++j) {
    const ScenarioConfig& s = *group[j];
    RunRow row_base = BaseRow(s, trial);
    row_base.detect_rate = base.detect_rate;
    row_base.corner_rms_px = base.corner_rms_px;
    row_base.corner_radial_bias_px = base.corner_radial_bias_px;
    row_base.corner_crlb_px = base.corner_crlb_px;
    row_base.frames_no_detection = base.frames_no_detection;
    row_base.measure_ms = j == 0 ? base.measure_ms : 0.0;
    if (!source) {
      AppendFailed(s, row_base, "measurements: " + why, &rows);
      continue;
    }
    ScenarioTrial runner(s, scene, *source, &cache, options);
    const size_t done_before = done.size();
    for (const MethodInstance* instance : s.EnabledMethods()) {
      const std::string key = runner.Key(*instance);
      const Done* earlier = nullptr;
      for (size_t d = 0; d < done_before; ++d) {
        if (done[d].name == instance->name && done[d].key == key) earlier = &done[d];
      }
      if (earlier != nullptr) {
        rows.push_back(CopyOf(rows[earlier->row], row_base));
      } else {
        rows.push_back(runner.Row(*instance, row_base, shared ? shared + j : nullptr));
      }
      done.push_back({instance->name, key, rows.size() - 1});
    }
  }
  return rows;
}

}  // namespace

std::string InstanceKey(const ScenarioConfig& scenario, const MethodInstance& instance) {
  std::deque<MethodInstance> defaults;
  return KeyOf(scenario, instance, 0, &defaults);
}

std::vector<RunRow> RunGroupTrial(const std::vector<const ScenarioConfig*>& group, int trial,
                                  ScenarioShared* shared, const GroupTrialOptions& options) {
  std::string error;
  try {
    return RunGroupTrialUnguarded(group, trial, shared, options);
  } catch (const std::exception& e) {  // e.g. std::bad_alloc: this trial fails, the sweep goes on.
    error = std::string("internal error: ") + e.what();
  }
  std::vector<RunRow> rows;
  for (const ScenarioConfig* s : group) AppendFailed(*s, BaseRow(*s, trial), error, &rows);
  return rows;
}

std::vector<RunRow> RunTrial(const ScenarioConfig& s, int trial, ScenarioShared* shared) {
  return RunGroupTrial({&s}, trial, shared, GroupTrialOptions());
}

}  // namespace calibench
