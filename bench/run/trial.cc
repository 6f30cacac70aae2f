#include "bench/run/trial.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <memory>
#include <optional>

#include "methods/options.h"
#include "methods/registry.h"
#include "util/format.h"

namespace calibench {
namespace {

// The trial's measurement source, its noise drawn from `seed`; *base gets the detection figures.
// Null (and *why) when the measurements cannot be produced.
std::unique_ptr<MeasurementSource> MakeSource(const ScenarioConfig& s, const SceneTruth& scene,
                                              uint64_t seed, RunRow* base, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<MeasurementSource> source;
  if (s.detections == Detections::kRendered) {
    auto rendered =
        RenderedSource::Create(scene, s.points.AprilGrids(), s.RenderingOptions(), seed, why);
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
    source = OracleSource::Create(scene, s.OracleSourceOptions(), seed, why);
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
  std::vector<std::optional<Rigid3>> pose_track;  // Rig tracking scenarios: at the report times.
};

// A proper parent_from_cam of an estimate, or none.
std::optional<Rigid3> PoseOf(const CameraEstimate& e) {
  if (!e.has_camera || e.improper || !e.parent_from_cam.rotation.allFinite() ||
      !e.parent_from_cam.translation.allFinite()) {
    return std::nullopt;
  }
  return e.parent_from_cam;
}

// What a method reports over time: theta_hat into ||theta~||(t), estimates into its trajectory.
class TrackSink final : public EstimateSink {
 public:
  TrackSink(ThetaTrack* theta, EstimateTrack* estimates, bool record_poses)
      : theta_(theta), estimates_(estimates), record_poses_(record_poses) {}
  void OnSeries(double t_s, const std::string& series, const Eigen::VectorXd& value) override {
    if (series != kThetaSeries || value.size() != 16) return;
    theta_->Add(t_s, value);
    ++theta_samples;
  }
  void OnEstimate(double t_s, const CameraEstimate& estimate) override {
    if (estimates_ != nullptr) estimates_->Add(t_s, estimate);
    if (record_poses_) poses.emplace_back(t_s, PoseOf(estimate));
  }
  // The poses at `times` (ascending), piecewise constant as EstimateTrack::Sample holds them.
  std::vector<std::optional<Rigid3>> SamplePoses(const std::vector<double>& times) const {
    std::vector<std::optional<Rigid3>> out;
    out.reserve(times.size());
    size_t next = 0;
    for (double t : times) {
      while (next < poses.size() && poses[next].first <= t + 1e-12) ++next;
      out.push_back(next > 0 ? poses[next - 1].second : std::nullopt);
    }
    return out;
  }
  int theta_samples = 0;
  std::vector<std::pair<double, std::optional<Rigid3>>> poses;

 private:
  ThetaTrack* theta_;
  EstimateTrack* estimates_;
  bool record_poses_;
};

// Runs the instances of one scenario of the group on the trial's measurements.
class ScenarioTrial {
 public:
  ScenarioTrial(const ScenarioConfig& s, const SceneTruth& scene, const MeasurementSource& source,
                int camera, TrialCache* cache, const GroupTrialOptions& options)
      : s_(s), scene_(scene), camera_(camera), cache_(cache), options_(options) {
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

  const MethodInput& Input() const { return input_; }
  // A rig scenario: every camera's input of this scenario and trial (camera 0 first) and which
  // of them this runner's is (MethodInput::rig_inputs), for the methods that estimate the rig
  // jointly.
  void LinkRig(std::vector<const MethodInput*> inputs, int camera) {
    input_.rig_inputs = std::move(inputs);
    input_.rig_camera = camera;
  }

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
      TrackSink sink(&track, tracks ? &estimates : nullptr, tracks && s_.rig.Any());
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
        if (s_.rig.Any()) outcome.pose_track = sink.SamplePoses(input.report_times_s);
      }
      return outcome;
    });
  }

  RunRow Row(const MethodInstance& instance, RunRow row, ScenarioShared* shared) {
    row.method = instance.name;
    row.camera = camera_;
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
    const EstimateMetrics m = EvaluateEstimate(r.status, e, s_.truth, input_.image_width,
                                               input_.image_height, input_.Frames().views);
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
      row.proj_err_px = m.projection.rms_px;
      row.proj_err_ratio = m.projection.ratio;
      if (s_.rig.Any() && r.IsUsable()) row.est_parent_from_cam = PoseOf(e);
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
    if (s_.rig.Any()) row.pose_track = outcome.pose_track;
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
    // A rig's cameras differ (their own intrinsics and views): one bound per camera.
    const std::string key = (camera_ > 0 ? "camera" + std::to_string(camera_) + ":" : "") +
                            std::string(ToString(model->model)) +
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
  int camera_;
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

// One camera's part of a trial of a group, ready to run: `group` holds the camera's scenarios
// (ScenarioConfig::CameraScenario; a single camera's: the group itself, which must outlive it),
// `scene` its truth (likewise), and its measurements draw their noise from `noise_seed`.
struct CameraGroupTrial {
  RunRow base;
  std::string why;  // Why there are no measurements (source null).
  std::unique_ptr<MeasurementSource> source;
  TrialCache cache;                                     // Shared by the group: same measurements.
  std::vector<std::unique_ptr<ScenarioTrial>> runners;  // Per scenario of the group, with source.
};

std::unique_ptr<CameraGroupTrial> PrepareCameraGroupTrial(
    const std::vector<const ScenarioConfig*>& group, const SceneTruth& scene, uint64_t noise_seed,
    int camera, int trial, const GroupTrialOptions& options) {
  auto prepared = std::make_unique<CameraGroupTrial>();
  prepared->base = BaseRow(*group.front(), trial);
  prepared->base.camera = camera;
  prepared->source = MakeSource(*group.front(), scene, noise_seed, &prepared->base, &prepared->why);
  if (prepared->source) {
    for (const ScenarioConfig* s : group) {
      prepared->runners.push_back(std::make_unique<ScenarioTrial>(
          *s, scene, *prepared->source, camera, &prepared->cache, options));
    }
  }
  return prepared;
}

// The rows of a prepared camera's part of a trial.
std::vector<RunRow> RunCameraGroupTrial(const std::vector<const ScenarioConfig*>& group,
                                        const CameraGroupTrial& prepared, int camera, int trial,
                                        ScenarioShared* shared) {
  const RunRow& base = prepared.base;
  std::vector<RunRow> rows;
  struct Done {
    std::string name, key;
    size_t row;
  };
  std::vector<Done> done;  // Rows computed so far in this group, for copies.
  for (size_t j = 0; j < group.size(); ++j) {
    const ScenarioConfig& s = *group[j];
    RunRow row_base = BaseRow(s, trial);
    row_base.camera = camera;
    row_base.detect_rate = base.detect_rate;
    row_base.corner_rms_px = base.corner_rms_px;
    row_base.corner_radial_bias_px = base.corner_radial_bias_px;
    row_base.corner_crlb_px = base.corner_crlb_px;
    row_base.frames_no_detection = base.frames_no_detection;
    row_base.measure_ms = j == 0 ? base.measure_ms : 0.0;
    if (!prepared.source) {
      AppendFailed(s, row_base, "measurements: " + prepared.why, &rows);
      continue;
    }
    ScenarioTrial& runner = *prepared.runners[j];
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

// The rig figures of camera c's row `rc` against camera 0's row `r0` (same scenario, trial and
// method): metrics/rig_metrics.h, the truth from the cameras' scenes.
RigRow RigFigures(const ScenarioConfig& s, int c, const SceneTruth& scene0,
                  const SceneTruth& scenec, const RunRow& r0, const RunRow& rc) {
  RigRow g;
  g.status = r0.status != "ok" ? r0.status : rc.status;
  const auto true_rel = [&](double t) {
    return scenec.CamFromParentAt(t) * scene0.ParentFromCamAt(t);
  };
  const double end_s = s.duration_s;
  RigErrorOptions options;
  options.focal_px = scene0.IntrinsicsAt(end_s).fkv_px;
  if (r0.est_parent_from_cam && rc.est_parent_from_cam) {
    const Rigid3 est = rc.est_parent_from_cam->Inverse() * *r0.est_parent_from_cam;
    g.errors = EvaluateRig(est, true_rel(end_s), options);
  }
  const size_t n = r0.pose_track.size();
  if (!s.Tracks() || n == 0 || rc.pose_track.size() != n || r0.track.size() != n) return g;
  // The segment after the last change that moves camera 0 or c (the start when none).
  g.segment_from_s = 0.0;
  for (size_t i = 0; i < s.truth_changes.size(); ++i) {
    const int moved = s.ChangeCamera(i);
    if (moved < 0 || moved == 0 || moved == c) {
      g.segment_from_s = std::max(g.segment_from_s, s.truth_changes[i].from_s);
    }
  }
  const TrackValues& tol = s.tracking.metrics.tolerance;
  g.rel_rot_tol_deg = std::max({tol[0], tol[1], tol[2]});  // roll, pitch, yaw (tracking.h).
  std::vector<double> times(n), rot(n, kUnset), baseline(n, kUnset), vdisp(n, kUnset);
  for (size_t i = 0; i < n; ++i) {
    times[i] = r0.track[i].t_s;
    if (!r0.pose_track[i] || !rc.pose_track[i]) continue;
    const Rigid3 est = rc.pose_track[i]->Inverse() * *r0.pose_track[i];
    const RigErrors e = EvaluateRig(est, true_rel(times[i]), options);
    rot[i] = e.rel_rot_err_norm_deg;
    baseline[i] = e.baseline_err_mm;
    vdisp[i] = e.vdisp_rms_px;
  }
  const double f = s.tracking.metrics.steady_fraction;
  g.rel_rot = EvaluateSegment(times, rot, g.segment_from_s, end_s, g.rel_rot_tol_deg, f);
  g.baseline_mm = EvaluateSegment(times, baseline, g.segment_from_s, end_s, kUnset, f);
  g.vdisp_rms_px = EvaluateSegment(times, vdisp, g.segment_from_s, end_s, kUnset, f);
  g.baseline_mm.reconverge_s = g.vdisp_rms_px.reconverge_s = kUnset;  // No tolerance: not used.
  return g;
}

std::vector<RunRow> RunGroupTrialUnguarded(const std::vector<const ScenarioConfig*>& group,
                                           int trial, ScenarioShared* shared,
                                           const GroupTrialOptions& options) {
  const ScenarioConfig& first = *group.front();
  const uint64_t trial_seed = first.TrialSeedOf(trial);
  if (!first.rig.Any()) {
    const SceneTruth scene = first.MakeScene(trial_seed);
    const auto prepared = PrepareCameraGroupTrial(group, scene, trial_seed, 0, trial, options);
    return RunCameraGroupTrial(group, *prepared, 0, trial, shared);
  }
  // A rig: every camera's measurements, then each camera's methods on its own (composition; the
  // joint methods see every camera's input through MethodInput::rig_inputs), camera by camera;
  // then the rig figures of each camera c >= 1 against camera 0, row by row (the cameras' rows
  // come in the same order).
  const int cameras = first.NumCameras();
  std::vector<SceneTruth> scenes;
  scenes.reserve(cameras);
  std::vector<std::vector<ScenarioConfig>> camera_scenarios(cameras);
  std::vector<std::vector<const ScenarioConfig*>> members(cameras);
  std::vector<std::unique_ptr<CameraGroupTrial>> prepared;
  prepared.reserve(cameras);
  for (int c = 0; c < cameras; ++c) {
    camera_scenarios[c].reserve(group.size());
    for (const ScenarioConfig* s : group) camera_scenarios[c].push_back(s->CameraScenario(c));
    for (const ScenarioConfig& s : camera_scenarios[c]) members[c].push_back(&s);
    scenes.push_back(first.MakeCameraScene(c, trial_seed));
    prepared.push_back(PrepareCameraGroupTrial(
        members[c], scenes.back(), ScenarioConfig::CameraSeed(trial_seed, c), c, trial, options));
  }
  const bool all_measured = std::all_of(prepared.begin(), prepared.end(),
                                        [](const auto& p) { return p->source != nullptr; });
  for (size_t j = 0; all_measured && j < group.size(); ++j) {
    std::vector<const MethodInput*> inputs;
    inputs.reserve(cameras);
    for (int c = 0; c < cameras; ++c) inputs.push_back(&prepared[c]->runners[j]->Input());
    for (int c = 0; c < cameras; ++c) prepared[c]->runners[j]->LinkRig(inputs, c);
  }
  std::vector<std::vector<RunRow>> by_camera;
  by_camera.reserve(cameras);
  for (int c = 0; c < cameras; ++c) {
    by_camera.push_back(RunCameraGroupTrial(members[c], *prepared[c], c, trial, shared));
  }
  std::vector<RunRow> rows;
  for (int c = 0; c < cameras; ++c) {
    for (size_t k = 0; k < by_camera[c].size(); ++k) {
      RunRow& row = by_camera[c][k];
      if (c > 0 && k < by_camera[0].size() && by_camera[0][k].method == row.method &&
          by_camera[0][k].scenario == row.scenario) {
        const ScenarioConfig* s = group.front();
        for (const ScenarioConfig* member : group) {
          if (member->name == row.scenario) s = member;
        }
        row.rig = RigFigures(*s, c, scenes[0], scenes[c], by_camera[0][k], row);
      }
    }
  }
  for (int c = 0; c < cameras; ++c) {
    for (RunRow& row : by_camera[c]) {
      row.pose_track.clear();  // Only the rig figures needed them.
      row.pose_track.shrink_to_fit();
      rows.push_back(std::move(row));
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
