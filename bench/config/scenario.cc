#include "bench/config/scenario.h"

#include <cmath>
#include <sstream>
#include <variant>

#include "util/random.h"

namespace calibench {

bool Reference::Any() const {
  return std::isfinite(fku_px) || std::isfinite(fkv_px) || std::isfinite(phi_deg) ||
         std::isfinite(u0_px) || std::isfinite(v0_px) || x_c.allFinite() ||
         std::isfinite(theta_err_below);
}

uint64_t ScenarioConfig::TrialSeedOf(int trial) const {
  const auto t = static_cast<uint64_t>(trial);
  if (sweep_point.measurement_index < 0 || paired_sweep) return TrialSeed(seed, t);
  const uint64_t point_seed = Mix64(
      seed ^ (0x5bd1e9955bd1e995ULL * (1 + static_cast<uint64_t>(sweep_point.measurement_index))));
  return TrialSeed(point_seed, t);
}

SceneTruth ScenarioConfig::MakeScene(uint64_t trial_seed) const {
  SceneTruth scene;
  scene.calibration_case = calibration_case;
  scene.intrinsics = truth.intrinsics;
  scene.parent_from_cam = truth.ParentFromCam();
  scene.allow_improper_rotation = truth.allow_improper_rotation;
  scene.changes = truth_changes;
  scene.points = points.xyz;
  scene.duration_s = duration_s;
  Motion::Options motion_options;
  motion_options.duration_s = duration_s;
  TwistProfile profile = motion;
  if (motion_random_phase) {
    // c cos(f t + p) + s sin(f t + p) = (c cos p + s sin p) cos f t + (s cos p - c sin p) sin f t.
    const double p = 2 * M_PI * Rng(trial_seed, RngStream::kMotionPhase).Uniform();
    const auto shift = [p](Eigen::Vector3d* c, Eigen::Vector3d* s) {
      const Eigen::Vector3d c0 = *c, s0 = *s;
      *c = c0 * std::cos(p) + s0 * std::sin(p);
      *s = s0 * std::cos(p) - c0 * std::sin(p);
    };
    shift(&profile.v_cos, &profile.v_sin);
    shift(&profile.w_cos, &profile.w_sin);
  }
  scene.motion = Motion(profile, motion_options);
  return scene;
}

std::string ScenarioConfig::CameraName(int c) const {
  if (rig.Any() && c >= 0 && c < NumCameras() && !rig.cameras[c].name.empty()) {
    return rig.cameras[c].name;
  }
  return "cam" + std::to_string(c);
}

ScenarioConfig ScenarioConfig::CameraScenario(int c) const {
  if (!rig.Any()) return *this;
  ScenarioConfig camera = *this;
  camera.truth_changes.clear();
  camera.truth_change_marks.clear();
  camera.truth_change_cameras.clear();
  for (size_t i = 0; i < truth_changes.size(); ++i) {
    if (ChangeCamera(i) >= 0 && ChangeCamera(i) != c) continue;
    camera.truth_changes.push_back(truth_changes[i]);
    if (i < truth_change_marks.size()) camera.truth_change_marks.push_back(truth_change_marks[i]);
  }
  // Every camera of a tracking rig tracks (the rig's figures over time need each one's
  // trajectory), also one that no change moves.
  if (Tracks()) camera.tracking.enabled = true;
  if (c == 0) return camera;
  const RigCameraConfig& rc = rig.cameras[c];
  camera.truth.intrinsics = rc.intrinsics;
  const Rigid3 parent_from_cam = truth.ParentFromCam() * rc.CamFromRig().Inverse();
  camera.truth.r_c = parent_from_cam.rotation;
  camera.truth.x_c = parent_from_cam.translation;
  if (rc.image_width > 0) {
    camera.image_width = rc.image_width;
    camera.image_height = rc.image_height;
  }
  return camera;
}

SceneTruth ScenarioConfig::MakeCameraScene(int c, uint64_t trial_seed) const {
  SceneTruth scene = MakeScene(trial_seed);
  if (!rig.Any()) return scene;
  scene.changes.clear();
  for (size_t i = 0; i < truth_changes.size(); ++i) {
    if (ChangeCamera(i) < 0) {
      scene.changes.push_back(truth_changes[i]);
    } else if (ChangeCamera(i) == c) {
      scene.rig_changes.push_back(truth_changes[i]);
    }
  }
  if (c != 0) scene.intrinsics = rig.cameras[c].intrinsics;
  if (c != 0 || !scene.rig_changes.empty()) {
    scene.rig_from_cam = rig.cameras[c].CamFromRig().Inverse();
  }
  return scene;
}

uint64_t ScenarioConfig::CameraSeed(uint64_t trial_seed, int c) {
  if (c == 0) return trial_seed;
  return TrialSeed(Mix64(trial_seed ^ 0x2545f4914f6cdd1dULL), static_cast<uint64_t>(c));
}

bool ScenarioConfig::CheckRig(int* camera, int* change, std::string* field,
                              std::string* why) const {
  *camera = -1;
  *change = -1;
  const auto fail = [&](int c, const std::string& f, const std::string& reason) {
    *camera = c;
    *field = f;
    *why = reason;
    return false;
  };
  if (rig.Any() && rig.cameras.size() < 2) {
    return fail(0, "rig.cameras",
                "a rig needs at least 2 cameras, got " + std::to_string(rig.cameras.size()));
  }
  for (size_t i = 0; i < truth_changes.size(); ++i) {
    const int c = ChangeCamera(i);
    if (c < 0) continue;
    *change = static_cast<int>(i);
    if (!rig.Any()) {
      return fail(-1, "truth.changes[" + std::to_string(i) + "].camera",
                  "names a camera of a rig, and the scenario has no `rig`");
    }
    if (c >= NumCameras()) {
      return fail(-1, "truth.changes[" + std::to_string(i) + "].camera",
                  std::to_string(c) + " names no camera (the rig has " +
                      std::to_string(NumCameras()) + ", indexed from 0)");
    }
    *change = -1;
  }
  if (!rig.Any()) return true;
  std::string reason;
  for (int c = 0; c < NumCameras(); ++c) {
    const RigCameraConfig& rc = rig.cameras[c];
    const std::string at = "rig.cameras[" + std::to_string(c) + "]";
    const std::string who = "camera '" + CameraName(c) + "'";
    if (!CheckRotation(rc.r, 1e-6, false, &reason)) {
      return fail(c, at + ".R", who + ": cam_from_rig: " + reason);
    }
    if (!rc.t_m.allFinite()) return fail(c, at + ".t_m", who + ": must be finite");
    if (c == 0) {
      if (rc.intrinsics_given) {
        return fail(c, at + ".intrinsics",
                    "camera 0 is the scenario's truth camera: its intrinsics are "
                    "truth.intrinsics (remove them here)");
      }
      if (rc.image_width > 0 &&
          (rc.image_width != image_width || rc.image_height != image_height)) {
        return fail(c, at + ".image_size",
                    "camera 0 is the scenario's truth camera: its image size is image_size");
      }
      if (!rc.r.isIdentity(1e-9) || !rc.t_m.isZero(1e-9)) {
        return fail(c, at,
                    "camera 0 defines the rig frame: its cam_from_rig must be the identity "
                    "(rpy_deg [0, 0, 0], t_m [0, 0, 0]); truth.R_C and x_C place the rig");
      }
      continue;
    }
    if (!rc.intrinsics_given) return fail(c, at + ".intrinsics", who + ": missing");
    if (!rc.intrinsics.Check(&reason)) return fail(c, at + ".intrinsics", who + ": " + reason);
    if (!(rc.t_m.norm() > 1e-9)) {
      return fail(c, at + ".t_m",
                  who + " is at camera 0's centre (baseline " + std::to_string(rc.t_m.norm()) +
                      " m): a rig's cameras are apart");
    }
  }
  // Every camera sees the points at t = 0: in front of it (the points' visibility check) and in
  // its image.
  for (int c = 1; c < NumCameras(); ++c) {
    const ScenarioConfig single = CameraScenario(c);
    const SceneTruth scene = MakeCameraScene(c, TrialSeedOf(0));
    const std::string at = "rig.cameras[" + std::to_string(c) + "]";
    const std::string who = "camera '" + CameraName(c) + "'";
    std::vector<Eigen::Vector3d> in_parent;
    std::vector<Eigen::Vector2d> pixels;
    if (!scene.Observe(0.0, &in_parent, &pixels, &reason)) {
      return fail(c, at,
                  who + " does not see the points (is it behind them, or turned away?): " + reason);
    }
    int inside = 0;
    for (size_t i = 0; i < pixels.size(); ++i) {
      const Eigen::Vector2d& p = pixels[i];
      const bool in =
          p.x() >= 0 && p.y() >= 0 && p.x() <= single.image_width && p.y() <= single.image_height;
      inside += in ? 1 : 0;
      if (!in && outside_image == OutsideImage::kFail) {
        std::ostringstream msg;
        msg << who << ": feature point " << i << " projects to (" << p.x() << ", " << p.y()
            << ") px at t = 0 s, outside its " << single.image_width << " x " << single.image_height
            << " image (measurements.outside_image: fail)";
        return fail(c, at, msg.str());
      }
    }
    if (inside == 0) {
      return fail(c, at,
                  who + " sees none of the " + std::to_string(pixels.size()) +
                      " points at t = 0 s (all outside its image)");
    }
  }
  return true;
}

std::vector<BoardLayout> ScenarioConfig::BoardLayouts() const {
  std::vector<BoardLayout> layouts;
  int first = 0;
  for (const PlacedBoard& b : points.boards) {
    layouts.push_back({b.board.CornersInBoard(), b.board.points_from_board, first});
    first += b.board.NumCorners();
  }
  for (const PlacedAprilGrid& g : points.aprilgrids) {
    layouts.push_back({g.grid.CornersInBoard(), g.grid.points_from_board, first});
    first += 4 * g.grid.NumTags();
  }
  return layouts;
}

RenderedSourceOptions ScenarioConfig::RenderingOptions() const {
  RenderedSourceOptions o = rendering;
  o.frame_rate_hz = measurements.sample_rate_hz;
  o.render.width = image_width;
  o.render.height = image_height;
  // Through an omnidirectional lens (unified, eucm, double-sphere) a tag's edges bend and its
  // corner squares sit past a homography's reach: the photometric fit is drawn through the
  // camera's lens (the truth's, as calibrate --images draws its last pass through its estimate),
  // unless the scenario gives a camera.
  const LensFamily lens = truth.intrinsics.family;
  if (!o.detection.camera && InfoOf(lens).sees_past_90) {
    o.detection.camera = truth.intrinsics;
  }
  return o;
}

OracleOptions ScenarioConfig::OracleSourceOptions() const {
  OracleOptions o = measurements;
  if (outside_image == OutsideImage::kFail) {
    o.require_in_image_width = image_width;
    o.require_in_image_height = image_height;
  }
  return o;
}

bool TrackingConfig::Check(std::string* why) const {
  if (!(report_rate_hz >= 0 && std::isfinite(report_rate_hz))) {
    if (why) *why = "report_rate_hz must be >= 0 (0: the frame times)";
    return false;
  }
  if (band_samples < 2) {
    if (why) *why = "band_samples must be >= 2";
    return false;
  }
  return metrics.Check(why);
}

namespace {

// ScenarioConfig::Check's parts: each returns false with the field and the reason.

// Frames per trial of each time grid, against kMaxFramesPerTrial.
bool CheckFramesPerTrial(const ScenarioConfig& s, std::string* field, std::string* reason) {
  const auto& m = s.measurements;
  const bool continuous_noise = m.noise.Active() && m.sample_rate_hz == 0;
  const std::pair<const char*, double> grids[] = {
      {"measurements.sample_rate_hz", s.duration_s * m.sample_rate_hz},
      {"measurements.eval_rate_hz", s.duration_s * m.eval_rate_hz},
      {"noise.hold_s", continuous_noise ? s.duration_s / m.noise.hold_s : 0.0}};
  for (const auto& [grid, frames] : grids) {
    if (frames <= kMaxFramesPerTrial) continue;
    std::ostringstream msg;
    msg << "gives " << frames << " frames (or noise draws) in duration_s = " << s.duration_s
        << " s, more than " << kMaxFramesPerTrial << " per trial";
    *field = grid;
    *reason = msg.str();
    return false;
  }
  return true;
}

// What detections: rendered needs: AprilGrids, a frame rate, no pixel noise of the oracle's, valid
// rendering options, a corner_error_grid among the grids.
bool CheckRendered(const ScenarioConfig& s, std::string* field, std::string* reason) {
  if (s.detections != Detections::kRendered) return true;
  auto fail = [&](const std::string& f, const std::string& r) {
    *field = f;
    *reason = r;
    return false;
  };
  const size_t grids = s.points.aprilgrids.size();
  if (grids == 0) {
    return fail("points",
                "detections: rendered needs AprilTag targets: points: {aprilgrids: [...]}");
  }
  if (!(s.measurements.sample_rate_hz > 0)) {
    return fail("measurements.sample_rate_hz", "detections: rendered needs a frame rate > 0");
  }
  if (s.diagnostics.corner_error_grid >= static_cast<int>(grids)) {
    return fail("diagnostics.corner_error_grid", std::to_string(s.diagnostics.corner_error_grid) +
                                                     " names no grid (the scenario has " +
                                                     std::to_string(grids) +
                                                     " aprilgrids, indexed from 0)");
  }
  if (s.measurements.noise.Active()) {
    return fail("noise",
                "rendered detections take their noise from the image "
                "(rendering.noise_sigma_gray, blur_sigma_px); remove noise.*");
  }
  *field = "rendering";
  return s.RenderingOptions().Check(reason);
}

// The reference and every method instance: known types, valid options, prerequisites that exist.
bool CheckMethods(const ScenarioConfig& s, std::string* field, std::string* reason) {
  auto fail = [&](const std::string& f, const std::string& r) {
    *field = f;
    *reason = r;
    return false;
  };
  if (!s.reference.method.empty() && s.FindMethod(s.reference.method) == nullptr) {
    return fail("reference.method", "no method instance named '" + s.reference.method + "'");
  }
  for (const MethodInstance& m : s.methods) {
    const std::string name = "methods." + m.name;
    if (m.method == nullptr) return fail(name, "unknown method type '" + m.type + "'");
    if (!m.method->Check(reason)) return fail(name, *reason);
    if (!(m.convergence_tol > 0)) return fail(name + ".convergence_tol", "must be > 0");
    for (const std::string& used : m.method->Prerequisites()) {
      if (s.FindMethod(used) == nullptr && FindMethodType(used) == nullptr) {
        return fail(name, "'" + used +
                              "' is neither a method instance of this scenario nor a method "
                              "type (" +
                              MethodTypeNames() + ")");
      }
      if (used == m.name) return fail(name, "a method cannot start from itself");
    }
  }
  return true;
}

}  // namespace

bool ScenarioConfig::Check(std::string* why) const {
  std::string field, reason;
  auto fail = [&](const std::string& key, const std::string& r) {
    if (why) *why = key + ": " + r;
    return false;
  };
  if (trials < 1) return fail("trials", "must be >= 1, got " + std::to_string(trials));
  if (!(duration_s > 0 && std::isfinite(duration_s)))
    return fail("duration_s", "must be positive and finite");
  if (!truth.intrinsics.Check(&reason)) return fail("truth.intrinsics", reason);
  if (!CheckRotation(truth.r_c, 1e-9, truth.allow_improper_rotation, &reason)) {
    return fail("truth.R_C", reason);
  }
  if (points.xyz.empty()) return fail("points", "at least one feature point is needed");
  for (size_t i = 0; i < truth_changes.size(); ++i) {
    if (!truth_changes[i].Check(duration_s, &reason)) {
      return fail("truth.changes[" + std::to_string(i) + "]", reason);
    }
  }
  if (!CheckChangesDoNotOverlap(truth_changes, &reason)) return fail("truth.changes", reason);
  if (!tracking.Check(&reason)) return fail("tracking", reason);
  if (!motion.Check(&reason)) return fail("motion", reason);
  if (!measurements.Check(&reason)) return fail("measurements", reason);
  if (!diagnostics.Check(&reason)) return fail("diagnostics", reason);
  if (diagnostics.tag_radial_bias_px != 0 &&
      (points.aprilgrids.empty() || !points.boards.empty())) {
    return fail("diagnostics.tag_radial_bias_px",
                "needs a target made of AprilGrids only (its points are the tags' corners, 4 by "
                "4)");
  }
  if (diagnostics.CornerErrorActive() && detections != Detections::kRendered) {
    return fail("diagnostics",
                "the corner error diagnostics (corner_error_*) need detections: "
                "rendered");
  }
  if (!CheckFramesPerTrial(*this, &field, &reason) || !CheckRendered(*this, &field, &reason)) {
    return fail(field, reason);
  }
  if (image_width < 1 || image_height < 1 || image_width > kMaxImageSide ||
      image_height > kMaxImageSide ||
      static_cast<double>(image_width) * image_height > kMaxImagePixels) {
    std::ostringstream msg;
    msg << "[" << image_width << ", " << image_height << "] is outside 1.." << kMaxImageSide
        << " px per side and " << kMaxImagePixels / 1e6 << " Mpx in all";
    return fail("image_size", msg.str());
  }
  if (!CheckMethods(*this, &field, &reason)) return fail(field, reason);
  int camera = -1, change = -1;
  if (!CheckRig(&camera, &change, &field, &reason)) return fail(field, reason);
  return true;
}

const MethodInstance* ScenarioConfig::FindMethod(const std::string& instance) const {
  for (const MethodInstance& m : methods) {
    if (m.name == instance) return &m;
  }
  return nullptr;
}

MethodInstance* ScenarioConfig::FindMethod(const std::string& instance) {
  for (MethodInstance& m : methods) {
    if (m.name == instance) return &m;
  }
  return nullptr;
}

std::vector<const MethodInstance*> ScenarioConfig::EnabledMethods() const {
  std::vector<const MethodInstance*> enabled;
  for (const MethodInstance& m : methods) {
    if (m.enabled) enabled.push_back(&m);
  }
  return enabled;
}

std::vector<MethodInstance> ScenarioConfig::DefaultMethods() {
  std::vector<MethodInstance> methods;
  for (const MethodType& t : MethodTypes())
    methods.push_back(MethodInstance::OfType(t.name, t.name));
  return methods;
}

std::vector<PlanarBoard> PointsConfig::Boards() const {
  std::vector<PlanarBoard> list;
  for (const PlacedBoard& b : boards) list.push_back(b.board);
  return list;
}

std::vector<AprilGrid> PointsConfig::AprilGrids() const {
  std::vector<AprilGrid> list;
  for (const PlacedAprilGrid& g : aprilgrids) list.push_back(g.grid);
  return list;
}

bool operator==(const PointsConfig& a, const PointsConfig& b) {
  if (a.xyz != b.xyz || a.boards.size() != b.boards.size() ||
      a.aprilgrids.size() != b.aprilgrids.size()) {
    return false;
  }
  for (size_t i = 0; i < a.boards.size(); ++i) {
    if (!(a.boards[i].board == b.boards[i].board) || a.boards[i].rpy_deg != b.boards[i].rpy_deg) {
      return false;
    }
  }
  for (size_t i = 0; i < a.aprilgrids.size(); ++i) {
    if (!(a.aprilgrids[i].grid == b.aprilgrids[i].grid) ||
        a.aprilgrids[i].rpy_deg != b.aprilgrids[i].rpy_deg) {
      return false;
    }
  }
  return true;
}

namespace {

// NaN == NaN here: an unset reference figure equals an unset one.
bool SameValue(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// Every declared field's value, in declaration order (equality of two configurations).
class Flatten final : public FieldVisitor {
 public:
  using Value = std::variant<double, long, uint64_t, bool, std::string, Eigen::Vector3d,
                             Eigen::Matrix3d, std::vector<Eigen::Vector3d>, const PointsConfig*,
                             const std::vector<MethodInstance>*>;
  std::vector<Value> values;

  void Field(const FieldSpec& f, double* v) override { Add(f, *v); }
  void Field(const FieldSpec& f, int* v) override { Add(f, static_cast<long>(*v)); }
  void Field(const FieldSpec& f, uint64_t* v) override { Add(f, *v); }
  void Field(const FieldSpec& f, bool* v) override { Add(f, *v); }
  void Field(const FieldSpec& f, std::string* v) override { Add(f, *v); }
  void Field(const FieldSpec& f, std::string* v, const Choices&) override { Add(f, *v); }
  void Field(const FieldSpec& f, Eigen::Vector3d* v) override { Add(f, *v); }
  void Field(const FieldSpec& f, Eigen::Matrix3d* v) override { Add(f, *v); }
  void Field(const FieldSpec& f, std::vector<Eigen::Vector3d>* v) override { Add(f, *v); }
  void Field(const FieldSpec& f, int* first, int* second) override {
    Add(f, static_cast<long>(*first));
    Add(f, static_cast<long>(*second));
  }
  void Section(const FieldSpec& f, const SectionOps& ops) override {
    if (!(f.flags & kNotCompared)) ops.visit(*this);
  }
  void List(const FieldSpec& f, const ListOps& ops) override {
    if (f.flags & kNotCompared) return;
    values.emplace_back(static_cast<long>(ops.size));
    for (size_t i = 0; i < ops.size; ++i) ops.visit(i, *this);
  }
  void Field(const FieldSpec& f, PointsConfig* v) override { Add(f, v); }
  void Field(const FieldSpec& f, std::vector<MethodInstance>* v) override { Add(f, v); }

  static bool Same(const Value& a, const Value& b) {
    if (a.index() != b.index()) return false;
    if (const double* x = std::get_if<double>(&a)) return SameValue(*x, std::get<double>(b));
    if (const auto* x = std::get_if<Eigen::Vector3d>(&a)) {
      const Eigen::Vector3d& y = std::get<Eigen::Vector3d>(b);
      for (int i = 0; i < 3; ++i)
        if (!SameValue((*x)[i], y[i])) return false;
      return true;
    }
    if (const auto* x = std::get_if<const PointsConfig*>(&a)) {
      return **x == *std::get<const PointsConfig*>(b);
    }
    if (const auto* x = std::get_if<const std::vector<MethodInstance>*>(&a)) {
      return **x == *std::get<const std::vector<MethodInstance>*>(b);
    }
    return a == b;
  }

 private:
  template <typename T>
  void Add(const FieldSpec& f, const T& v) {
    if (!(f.flags & kNotCompared)) values.emplace_back(v);
  }
};

std::vector<Flatten::Value> Values(const ScenarioConfig& s) {
  Flatten flatten;
  Visit(flatten, const_cast<ScenarioConfig&>(s));  // NOLINT: Flatten only reads.
  return std::move(flatten.values);
}

}  // namespace

const EnumNames<ReportRole>& ReportRoleNames() {
  static const EnumNames<ReportRole> names{{{ReportRole::kNone, "none"},
                                            {ReportRole::kNoise, "noise"},
                                            {ReportRole::kPoints, "points"},
                                            {ReportRole::kGain, "gain"},
                                            {ReportRole::kDynamic, "dynamic"},
                                            {ReportRole::kRig, "rig"}}};
  return names;
}

bool operator==(const Reference& a, const Reference& b) {
  bool x_c = true;
  for (int i = 0; i < 3; ++i) x_c = x_c && SameValue(a.x_c[i], b.x_c[i]);
  return a.source == b.source && a.method == b.method && SameValue(a.fku_px, b.fku_px) &&
         SameValue(a.fkv_px, b.fkv_px) && SameValue(a.phi_deg, b.phi_deg) &&
         SameValue(a.u0_px, b.u0_px) && SameValue(a.v0_px, b.v0_px) && x_c &&
         SameValue(a.theta_err_below, b.theta_err_below);
}

bool operator==(const SweepPoint& a, const SweepPoint& b) {
  return a.sweep == b.sweep && a.index == b.index && a.measurement_index == b.measurement_index &&
         a.params == b.params;
}

// How the points and the motion were written (a preset, a random box) is not compared: the
// resolved YAML writes the points and the twist themselves, which are.
bool operator==(const ScenarioConfig& a, const ScenarioConfig& b) {
  const std::vector<Flatten::Value> x = Values(a), y = Values(b);
  if (x.size() != y.size()) return false;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!Flatten::Same(x[i], y[i])) return false;
  }
  return true;
}

}  // namespace calibench
