// Rig metrics: an estimated relative pose of camera c, cam_c_from_cam_0 (camera/rig.h: the rig
// frame is camera 0's), against the true one, and what its error does to stereo.
//
//   relative rotation   e = Log(R_est R_true^T) in degrees: turns about camera c's x, y, z axes
//                       (pitch, yaw, roll for small angles), and its norm (the geodesic angle);
//   baseline            |t_est| - |t_true| in mm (t: the translation of cam_c_from_cam_0);
//   vertical disparity  the rectification a stereo pipeline makes from the ESTIMATED rig
//                       (Bouguet's: both cameras turned so the estimated baseline is the x axis,
//                       ideal pinholes of focal f, no lens: rays, not pixels), applied to the TRUE
//                       rays of a grid of points on a fronto-parallel plane (in camera 0's frame,
//                       z = plane_depth_m, directions +-20 deg across, +-15 deg down, 5 x 5). y of
//                       camera c minus y of camera 0, px; 0 for an exact rig. A rotation error d
//                       about camera c's x axis gives about f tan(d) everywhere;
//   depth               a point on camera 0's optical axis at depth Z: Z_est = f B_est / d_x from
//                       the horizontal disparity d_x in the estimated rectification, against the
//                       true depth in the true one (f B_true / d_x,true, exactly Z's rectified
//                       depth), in percent (signed). A baseline error alone gives
//                       100 (B_est - B_true) / B_true; a yaw error d about 100 (-Z d / B).
// The rectified focal length f is the caller's (the bench uses camera 0's true f*kv).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "camera/pose.h"

namespace calibench {

struct RigErrorOptions {
  double focal_px = 500.0;      // f of the ideal rectified cameras.
  double plane_depth_m = 10.0;  // The vertical disparity's plane, in camera 0's frame.
  double depth_near_m = 10.0, depth_far_m = 30.0;  // The depth errors' two depths.
};

struct RigErrors {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector3d rel_rot_err_deg = Eigen::Vector3d::Constant(kNaN);  // Per camera c axis.
  double rel_rot_err_norm_deg = kNaN;
  double baseline_err_mm = kNaN;
  double vdisp_rms_px = kNaN, vdisp_max_px = kNaN;  // Over the plane's grid; max of |.|.
  double depth_err_near_pct = kNaN, depth_err_far_pct = kNaN;
};

// The errors of `est` (cam_c_from_cam_0 as estimated) against `truth`.
RigErrors EvaluateRig(const Rigid3& est, const Rigid3& truth, const RigErrorOptions& options);

// The vertical disparities of the plane's grid (RigErrors::vdisp_*), row by row, px.
std::vector<double> PlaneVerticalDisparitiesPx(const Rigid3& est, const Rigid3& truth,
                                               const RigErrorOptions& options);

// The rectifying rotation of a rig with camera c's centre at `centre_in_cam0` (camera 0's frame):
// rows e1 = the baseline's direction, e2 = z x e1 normalised (the image's down), e3 = e1 x e2.
Eigen::Matrix3d RectifyingRotation(const Eigen::Vector3d& centre_in_cam0);

}  // namespace calibench

namespace calibench {

// A rig figure over time (errors at report times, NaN before a method's first estimate: outside
// every tolerance) on the segment [from_s, to_s), as tracking.h's events: the first t - from_s
// after which |error| stays <= tol until the segment's end (NaN if its last sample is outside),
// the median |error| over its last steady_fraction and the largest |error|.
struct SegmentFigures {
  double reconverge_s = std::numeric_limits<double>::quiet_NaN();
  double steady_err = std::numeric_limits<double>::quiet_NaN();
  double peak_err = std::numeric_limits<double>::quiet_NaN();
};
SegmentFigures EvaluateSegment(const std::vector<double>& times_s,
                               const std::vector<double>& errors, double from_s, double to_s,
                               double tol, double steady_fraction);

}  // namespace calibench
