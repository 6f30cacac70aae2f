#include "bench/scenario.h"

#include <cmath>
#include <sstream>

#include "core/random.h"

namespace calibench {

CameraSpec AdaptiveMethodConfig::ThesisInitialGuess() {
  CameraSpec c;
  c.intrinsics.fku_px = 820;
  c.intrinsics.fkv_px = 810;
  c.intrinsics.phi_deg = 90;
  c.intrinsics.u0_px = 320;
  c.intrinsics.v0_px = 240;
  c.r_c << -1, 0, 0, 0, 0, 1, 0, 1, 0;
  c.x_c = Eigen::Vector3d(0, -2, 0.5);
  return c;
}

bool Reference::Any() const {
  return std::isfinite(fku_px) || std::isfinite(fkv_px) || std::isfinite(phi_deg) ||
         std::isfinite(u0_px) || std::isfinite(v0_px) || x_c.allFinite() ||
         std::isfinite(theta_err_below);
}

uint64_t ScenarioConfig::TrialSeedOf(int trial) const {
  const auto t = static_cast<uint64_t>(trial);
  if (sweep_point.measurement_index < 0) return TrialSeed(seed, t);
  const uint64_t point_seed = Mix64(
      seed ^ (0x5bd1e9955bd1e995ULL * (1 + static_cast<uint64_t>(sweep_point.measurement_index))));
  return TrialSeed(point_seed, t);
}

SceneTruth ScenarioConfig::MakeScene() const {
  SceneTruth scene;
  scene.calibration_case = calibration_case;
  scene.intrinsics = truth.intrinsics;
  scene.parent_from_cam = truth.ParentFromCam();
  scene.allow_improper_rotation = truth.allow_improper_rotation;
  scene.points = points;
  scene.duration_s = duration_s;
  Motion::Options motion_options;
  motion_options.duration_s = duration_s;
  scene.motion = Motion(motion, motion_options);
  return scene;
}

std::vector<ScenarioConfig::BoardLayout> ScenarioConfig::BoardLayouts() const {
  std::vector<BoardLayout> layouts;
  int first = 0;
  for (const PlanarBoard& b : boards) {
    layouts.push_back({b.CornersInBoard(), b.points_from_board, first});
    first += b.NumCorners();
  }
  for (const AprilGrid& g : aprilgrids) {
    layouts.push_back({g.CornersInBoard(), g.points_from_board, first});
    first += 4 * g.NumTags();
  }
  return layouts;
}

RenderedSourceOptions ScenarioConfig::RenderingOptions() const {
  RenderedSourceOptions o = rendering;
  o.frame_rate_hz = measurements.sample_rate_hz;
  o.render.width = image_width;
  o.render.height = image_height;
  return o;
}

OracleOptions ScenarioConfig::OracleSourceOptions() const {
  OracleOptions o = measurements;
  if (outside_image == "fail") {
    o.require_in_image_width = image_width;
    o.require_in_image_height = image_height;
  }
  return o;
}

bool ScenarioConfig::Check(std::string* why) const {
  std::string reason;
  auto fail = [&](const std::string& field, const std::string& r) {
    if (why) *why = field + ": " + r;
    return false;
  };
  if (trials < 1) return fail("trials", "must be >= 1, got " + std::to_string(trials));
  if (!(duration_s > 0 && std::isfinite(duration_s)))
    return fail("duration_s", "must be positive and finite");
  if (!truth.intrinsics.Check(&reason)) return fail("truth.intrinsics", reason);
  if (!CheckRotation(truth.r_c, 1e-9, truth.allow_improper_rotation, &reason)) {
    return fail("truth.R_C", reason);
  }
  if (points.empty()) return fail("points", "at least one feature point is needed");
  if (!motion.Check(&reason)) return fail("motion", reason);
  if (!measurements.Check(&reason)) return fail("measurements", reason);
  // Frames per trial of each time grid, against kMaxFramesPerTrial.
  const bool continuous_noise = measurements.noise.Active() && measurements.sample_rate_hz == 0;
  const std::pair<const char*, double> grids[] = {
      {"measurements.sample_rate_hz", duration_s * measurements.sample_rate_hz},
      {"measurements.eval_rate_hz", duration_s * measurements.eval_rate_hz},
      {"noise.hold_s", continuous_noise ? duration_s / measurements.noise.hold_s : 0.0}};
  for (const auto& [field, frames] : grids) {
    if (frames <= kMaxFramesPerTrial) continue;
    std::ostringstream msg;
    msg << "gives " << frames << " frames (or noise draws) in duration_s = " << duration_s
        << " s, more than " << kMaxFramesPerTrial << " per trial";
    return fail(field, msg.str());
  }
  if (detections == "rendered") {
    if (aprilgrids.empty()) {
      return fail("points",
                  "detections: rendered needs AprilTag targets: points: {aprilgrids: [...]}");
    }
    if (!(measurements.sample_rate_hz > 0)) {
      return fail("measurements.sample_rate_hz", "detections: rendered needs a frame rate > 0");
    }
    if (measurements.noise.Active()) {
      return fail("noise",
                  "rendered detections take their noise from the image "
                  "(rendering.noise_sigma_gray, blur_sigma_px); remove noise.*");
    }
    if (!RenderingOptions().Check(&reason)) return fail("rendering", reason);
  } else if (detections != "oracle") {
    return fail("measurements.detections", "must be oracle or rendered, got '" + detections + "'");
  }
  if (adaptive.enabled) {
    if (!adaptive.options.Check(&reason)) return fail("methods.adaptive", reason);
    if (!adaptive.initial.intrinsics.Check(&reason)) {
      return fail("methods.adaptive.initial.intrinsics", reason);
    }
    if (!CheckRotation(adaptive.initial.r_c, 1e-9, adaptive.initial.allow_improper_rotation,
                       &reason)) {
      return fail("methods.adaptive.initial.R_C", reason);
    }
    if (!(adaptive.convergence_tol > 0)) {
      return fail("methods.adaptive.convergence_tol", "must be > 0");
    }
  }
  return true;
}

}  // namespace calibench
