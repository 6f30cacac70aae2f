// The two calibration cases of the thesis (spec "The two cases") as one measurement model.
//
//   fixed camera:  camera still in W; feature points ride on the moving body.
//                  x_bar_i(t) = world_from_body(t) * point_in_body_i          (a point in W)
//                  parent frame P = W, parent_from_cam = {R_C, x_C} = camera in W.
//   moving camera: camera rides on the body; feature points are fixed in W.
//                  x_bar_i(t) = body_from_world(t) * point_in_world_i         (a point in B)
//                  parent frame P = B, parent_from_cam = {R_C, x_C} = camera in B.
//
// In both, p_i(t) = Project(A, cam_from_parent * x_bar_i(t)): one constant M = A [R | t] with
// R = R_C^T, t = -R_C^T x_C. The body starts at world_from_body(0) = identity, so the points the
// thesis lists (x_bar at t = 0) are point_in_body (fixed) or point_in_world (moving) directly.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/motion.h"
#include "core/pose.h"

namespace calibench {

enum class CalibrationCase { kFixedCamera, kMovingCamera };
const char* ToString(CalibrationCase c);

// A camera as a scenario states it: intrinsics plus its pose in the parent frame, (R_C, x_C) as the
// thesis writes them (parent_from_cam). The truth of a scenario and an estimator's initial guess.
struct CameraSpec {
  CameraIntrinsics intrinsics;
  Eigen::Matrix3d r_c = Eigen::Matrix3d::Identity();
  Eigen::Vector3d x_c = Eigen::Vector3d::Zero();
  bool allow_improper_rotation = false;  // Opt-in for det(R_C) = -1 (the thesis's printed cameras).
  Rigid3 ParentFromCam() const { return {r_c, x_c}; }
};
bool operator==(const CameraSpec& a, const CameraSpec& b);
inline bool operator!=(const CameraSpec& a, const CameraSpec& b) { return !(a == b); }

struct SceneTruth {
  CalibrationCase calibration_case = CalibrationCase::kMovingCamera;
  CameraIntrinsics intrinsics;
  Rigid3 parent_from_cam;  // {R_C, x_C} of the thesis.
  bool allow_improper_rotation = false;
  // Fixed camera: point_in_body; moving camera: point_in_world (both = x_bar at t = 0).
  std::vector<Eigen::Vector3d> points;
  Motion motion;
  double duration_s = 240.0;

  Rigid3 CamFromParent() const { return parent_from_cam.Inverse(); }
  // Where the points frame (body for a fixed camera, world for a moving one) is in P at time t.
  Rigid3 ParentFromPoints(double t) const;
  // x_bar_i(t) without its homogeneous 1: point i in the parent frame P at time t.
  Eigen::Vector3d PointInParent(int i, double t) const;
  // All points at time t (x_bar in P, and their exact pixels). Returns false, naming the point,
  // when a point is not in front of the camera.
  bool Observe(double t, std::vector<Eigen::Vector3d>* points_in_parent,
               std::vector<Eigen::Vector2d>* pixels, std::string* why) const;

  // Valid intrinsics, an orthonormal R_C (det +1 unless allow_improper_rotation), at least one
  // point, a positive duration and a valid twist profile.
  bool Check(std::string* why) const;
};

}  // namespace calibench
