#include "batch/jackknife.h"

#include <cmath>

namespace calibench {

bool JackknifeOptions::Check(std::string* why) const {
  std::string msg;
  if (refine.shared_pose) msg = "the jackknife leaves out views: it needs per-view poses";
  if (min_views < 3) msg = "min_views must be >= 3, got " + std::to_string(min_views);
  if (msg.empty()) return refine.Check(why);
  if (why) *why = msg;
  return false;
}

JackknifeResult JackknifeIntrinsics(const std::vector<View>& views, const RefineResult& full,
                                    const JackknifeOptions& options) {
  const SummaryClock clock;
  JackknifeResult result;
  result.num_views = static_cast<int>(views.size());
  result.intrinsics_std.fill(std::nan(""));
  std::string why;
  if (!options.Check(&why)) return clock.Finish(&result, MethodStatus::kFailed, why);
  if (!options.view_ids.empty() && options.view_ids.size() != views.size()) {
    return clock.Finish(&result, MethodStatus::kFailed, "view_ids must name every view");
  }
  if (!full.IsUsable() || full.cam_from_object.size() != views.size()) {
    return clock.Finish(&result, MethodStatus::kFailed,
                        "needs the usable full fit of the same views (one pose per view)");
  }
  const int n = result.num_views;
  if (n < options.min_views) {
    return clock.Finish(&result, MethodStatus::kFailed,
                        std::to_string(n) + " views: the jackknife needs at least " +
                            std::to_string(options.min_views));
  }
  RefineOptions refine = options.refine;
  refine.compute_covariance = false;
  refine.compute_pose_covariance = false;
  std::vector<View> kept;
  std::vector<Rigid3> kept_poses;
  kept.reserve(views.size() - 1);
  kept_poses.reserve(views.size() - 1);
  for (int left_out = 0; left_out < n; ++left_out) {
    kept.clear();
    kept_poses.clear();
    refine.view_names.clear();
    for (int v = 0; v < n; ++v) {
      if (v == left_out) continue;
      kept.push_back(views[v]);
      kept_poses.push_back(full.cam_from_object[v]);
      // Failures name the input's view.
      refine.view_names.push_back(
          "view " + std::to_string(options.view_ids.empty() ? v : options.view_ids[v]));
    }
    const RefineResult refit = RefineCalibration(kept, full.intrinsics, kept_poses, refine);
    result.iterations += refit.iterations;
    if (!refit.IsUsable()) {
      const int id = options.view_ids.empty() ? left_out : options.view_ids[left_out];
      return clock.Finish(&result, MethodStatus::kFailed,
                          "without view " + std::to_string(id) + ": " + refit.message);
    }
    result.leave_one_out.push_back(refit.intrinsics);
    result.leave_one_out_poses.push_back(refit.cam_from_object);
  }
  std::vector<IntrinsicsArray> params;
  for (const CameraIntrinsics& c : result.leave_one_out) params.push_back(c.Params());
  std::vector<bool> fixed(PinholeSkewCamera::kNumParams, false);
  for (int p : FixedIntrinsics(refine.model, refine.estimate_skew)) fixed[p] = true;
  for (int p : refine.extra_fixed_intrinsics) fixed[p] = true;
  for (int p = 0; p < PinholeSkewCamera::kNumParams; ++p) {
    if (fixed[p]) continue;
    double mean = 0;
    for (const IntrinsicsArray& a : params) mean += a[p] / n;
    double sum_sq = 0;
    for (const IntrinsicsArray& a : params) sum_sq += (a[p] - mean) * (a[p] - mean);
    result.intrinsics_std[p] = std::sqrt((n - 1.0) / n * sum_sq);
  }
  return clock.Finish(&result, MethodStatus::kOk, "");
}

bool RigJackknifeOptions::Check(std::string* why) const {
  if (min_frames < 3) {
    if (why) *why = "min_frames must be >= 3, got " + std::to_string(min_frames);
    return false;
  }
  return refine.Check(why);
}

RigJackknifeResult JackknifeRig(const std::vector<RigFrame>& frames, const RigRefineResult& full,
                                const RigJackknifeOptions& options) {
  const SummaryClock clock;
  RigJackknifeResult result;
  const int n = static_cast<int>(frames.size());
  result.num_frames = n;
  std::string why;
  if (!options.Check(&why)) return clock.Finish(&result, MethodStatus::kFailed, why);
  if (!full.IsUsable() || full.rig_from_board.size() != frames.size()) {
    return clock.Finish(&result, MethodStatus::kFailed,
                        "needs the usable full fit of the same frames (one pose per frame)");
  }
  if (n < options.min_frames) {
    return clock.Finish(&result, MethodStatus::kFailed,
                        std::to_string(n) + " frames: the jackknife needs at least " +
                            std::to_string(options.min_frames));
  }
  const int num_cameras = full.rig.NumCameras();
  RigRefineOptions refine = options.refine;
  refine.compute_covariance = false;
  // Per camera: each refit's baseline (mm), unit baseline, rotation vector (deg).
  std::vector<std::vector<double>> baseline_mm(num_cameras);
  std::vector<std::vector<Eigen::Vector3d>> direction(num_cameras), rotation_deg(num_cameras);
  std::vector<RigFrame> kept;
  std::vector<Rigid3> kept_poses;
  for (int left_out = 0; left_out < n; ++left_out) {
    kept.clear();
    kept_poses.clear();
    for (int f = 0; f < n; ++f) {
      if (f == left_out) continue;
      kept.push_back(frames[f]);
      kept_poses.push_back(full.rig_from_board[f]);
    }
    const RigRefineResult refit = RefineRig(kept, full.rig, kept_poses, refine);
    result.iterations += refit.iterations;
    if (!refit.IsUsable()) {
      const std::string name = frames[left_out].name.empty() ? "frame " + std::to_string(left_out)
                                                             : frames[left_out].name;
      return clock.Finish(&result, MethodStatus::kFailed, "without " + name + ": " + refit.message);
    }
    for (int c = 1; c < num_cameras; ++c) {
      const Eigen::Vector3d centre = refit.rig.CentreInRig(c);
      baseline_mm[c].push_back(centre.norm() * 1000.0);
      direction[c].push_back(centre.normalized());
      rotation_deg[c].push_back(refit.rig.RelativeRotationDeg(c));
    }
  }
  const double scale = (n - 1.0) / n;
  result.pose.assign(num_cameras, RigPoseUncertainty());
  for (int c = 1; c < num_cameras; ++c) {
    double mean_b = 0;
    Eigen::Vector3d mean_u = Eigen::Vector3d::Zero(), mean_r = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) {
      mean_b += baseline_mm[c][i] / n;
      mean_u += direction[c][i];
      mean_r += rotation_deg[c][i] / n;
    }
    mean_u.normalize();
    double sum_b = 0, sum_angle = 0;
    Eigen::Vector3d sum_r = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) {
      sum_b += (baseline_mm[c][i] - mean_b) * (baseline_mm[c][i] - mean_b);
      const double angle =
          std::atan2(direction[c][i].cross(mean_u).norm(), direction[c][i].dot(mean_u));
      sum_angle += angle * angle;
      sum_r += (rotation_deg[c][i] - mean_r).cwiseAbs2();
    }
    RigPoseUncertainty& u = result.pose[c];
    u.baseline_std_mm = std::sqrt(scale * sum_b);
    u.baseline_direction_std_deg = std::sqrt(scale * sum_angle) * 180.0 / M_PI;
    u.rotation_std_deg = (scale * sum_r).cwiseSqrt();
  }
  return clock.Finish(&result, MethodStatus::kOk, "");
}

}  // namespace calibench
