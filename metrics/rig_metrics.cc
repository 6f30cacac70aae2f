#include "metrics/rig_metrics.h"

#include <algorithm>
#include <cmath>

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A point X of camera 0's true frame through both true cameras, rectified with the rig `rig`
// (cam_c_from_cam_0): its rectified image coordinates (x, y) in camera 0 and camera c, px.
struct RectifiedPair {
  Eigen::Vector2d cam0, camc;
};
RectifiedPair Rectify(const Eigen::Vector3d& x, const Rigid3& rig, const Rigid3& truth,
                      double focal_px) {
  const Eigen::Matrix3d rect = RectifyingRotation(-(rig.rotation.transpose() * rig.translation));
  const Eigen::Vector3d ray0 = rect * x;
  // Camera c's true ray, turned into camera 0's orientation as the rig says it is.
  const Eigen::Vector3d rayc = rect * (rig.rotation.transpose() * (truth * x));
  return {focal_px * ray0.head<2>() / ray0.z(), focal_px * rayc.head<2>() / rayc.z()};
}

double DepthFromDisparity(double depth_m, const Rigid3& rig, const Rigid3& truth, double focal_px) {
  const RectifiedPair p = Rectify(Eigen::Vector3d(0, 0, depth_m), rig, truth, focal_px);
  const double disparity_px = p.cam0.x() - p.camc.x();
  if (!(disparity_px > 0)) return std::numeric_limits<double>::quiet_NaN();
  return focal_px * rig.translation.norm() / disparity_px;
}

}  // namespace

Eigen::Matrix3d RectifyingRotation(const Eigen::Vector3d& centre_in_cam0) {
  const Eigen::Vector3d e1 = centre_in_cam0.normalized();
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitZ().cross(e1);
  if (e2.norm() < 1e-9) e2 = Eigen::Vector3d::UnitY();  // A baseline along the optical axis.
  e2.normalize();
  const Eigen::Vector3d e3 = e1.cross(e2);
  Eigen::Matrix3d r;
  r.row(0) = e1.transpose();
  r.row(1) = e2.transpose();
  r.row(2) = e3.transpose();
  return r;
}

std::vector<double> PlaneVerticalDisparitiesPx(const Rigid3& est, const Rigid3& truth,
                                               const RigErrorOptions& options) {
  std::vector<double> disparities;
  const double z = options.plane_depth_m;
  for (int row = 0; row < 5; ++row) {
    for (int col = 0; col < 5; ++col) {
      const double across = (-20.0 + 10.0 * col) * kDeg, down = (-15.0 + 7.5 * row) * kDeg;
      const Eigen::Vector3d x(z * std::tan(across), z * std::tan(down), z);
      const RectifiedPair p = Rectify(x, est, truth, options.focal_px);
      disparities.push_back(p.camc.y() - p.cam0.y());
    }
  }
  return disparities;
}

RigErrors EvaluateRig(const Rigid3& est, const Rigid3& truth, const RigErrorOptions& options) {
  RigErrors e;
  if (!est.rotation.allFinite() || !est.translation.allFinite()) return e;
  e.rel_rot_err_deg = LogSO3(est.rotation * truth.rotation.transpose()) / kDeg;
  e.rel_rot_err_norm_deg = e.rel_rot_err_deg.norm();
  e.baseline_err_mm = 1000.0 * (est.translation.norm() - truth.translation.norm());
  const std::vector<double> v = PlaneVerticalDisparitiesPx(est, truth, options);
  double sum2 = 0.0, max_abs = 0.0;
  for (double d : v) {
    sum2 += d * d;
    max_abs = std::max(max_abs, std::abs(d));
  }
  e.vdisp_rms_px = std::sqrt(sum2 / v.size());
  e.vdisp_max_px = max_abs;
  const auto depth_err = [&](double z) {
    const double z_est = DepthFromDisparity(z, est, truth, options.focal_px);
    const double z_ref = DepthFromDisparity(z, truth, truth, options.focal_px);
    return 100.0 * (z_est - z_ref) / z_ref;
  };
  e.depth_err_near_pct = depth_err(options.depth_near_m);
  e.depth_err_far_pct = depth_err(options.depth_far_m);
  return e;
}

}  // namespace calibench

namespace calibench {

SegmentFigures EvaluateSegment(const std::vector<double>& times_s,
                               const std::vector<double>& errors, double from_s, double to_s,
                               double tol, double steady_fraction) {
  SegmentFigures out;
  const double steady_from = to_s - steady_fraction * (to_s - from_s);
  std::vector<double> steady;
  double peak = -1.0, last_outside = -1.0, first_after = out.reconverge_s;
  bool any = false, pending = false;
  for (size_t i = 0; i < times_s.size() && i < errors.size(); ++i) {
    const double t = times_s[i];
    if (t < from_s || t >= to_s) continue;
    any = true;
    const bool valid = !std::isnan(errors[i]);
    const double error = valid ? std::abs(errors[i]) : std::numeric_limits<double>::infinity();
    if (valid) peak = std::max(peak, error);
    if (valid && t >= steady_from) steady.push_back(error);
    if (!(error <= tol)) {
      last_outside = t;
      pending = true;
    } else if (pending) {
      first_after = t;
      pending = false;
    }
  }
  if (!any) return out;
  if (!pending) out.reconverge_s = last_outside < 0 ? 0.0 : first_after - from_s;
  if (peak >= 0) out.peak_err = peak;
  if (!steady.empty()) {
    std::sort(steady.begin(), steady.end());
    const size_t n = steady.size();
    out.steady_err = n % 2 ? steady[n / 2] : 0.5 * (steady[n / 2 - 1] + steady[n / 2]);
  }
  return out;
}

}  // namespace calibench
