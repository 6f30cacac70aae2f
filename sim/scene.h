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
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/pose.h"
#include "sim/motion.h"

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

// A change of the calibration over time (dynamic calibration, spec dynamic-calibration.md): a step
// at from_s (= to_s), or a ramp reaching its full deltas linearly from from_s to to_s. At time t
// with fraction f = Fraction(t) in [0, 1]:
//   the mount rotates:  parent_from_cam.rotation <- R(f * rpy_deg) * parent_from_cam.rotation,
//                        R = yaw-pitch-roll about the parent's z, y and x axes (camera/pose.h);
//   the camera shifts:  x_C <- x_C + f * x_m (parent frame, m);
//   the intrinsics:     f*ku, f*kv, u0, v0 (px) and phi (deg) <- + f * delta.
// Changes apply in list order on top of the scenario's initial camera.
struct CalibrationChange {
  enum class Kind { kStep, kRamp };
  Kind kind = Kind::kStep;
  double from_s = 0.0, to_s = 0.0;  // A step: from_s = to_s = at_s.
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d x_m = Eigen::Vector3d::Zero();
  double fku_px = 0.0, fkv_px = 0.0, u0_px = 0.0, v0_px = 0.0, phi_deg = 0.0;

  // 0 before from_s, 1 from to_s on (a step: from at_s on), linear in between.
  double Fraction(double t_s) const;
  bool RotatesMount() const { return !rpy_deg.isZero(0); }
  bool ShiftsCamera() const { return !x_m.isZero(0); }
  bool ChangesIntrinsics() const {
    return fku_px != 0 || fkv_px != 0 || u0_px != 0 || v0_px != 0 || phi_deg != 0;
  }
  // Finite deltas, ordered times inside [0, duration_s], something that changes.
  bool Check(double duration_s, std::string* why) const;
};
bool operator==(const CalibrationChange& a, const CalibrationChange& b);

// No two ramps may change one quantity (the mount rotation, the position, one intrinsic) over
// overlapping intervals; false with *why naming both.
bool CheckChangesDoNotOverlap(const std::vector<CalibrationChange>& changes, std::string* why);

struct SceneTruth {
  CalibrationCase calibration_case = CalibrationCase::kMovingCamera;
  CameraIntrinsics intrinsics;  // At t = 0 (see changes).
  Rigid3 parent_from_cam;       // {R_C, x_C} of the thesis, at t = 0 (see changes).
  bool allow_improper_rotation = false;
  std::vector<CalibrationChange> changes;  // Empty: a static calibration.
  // Fixed camera: point_in_body; moving camera: point_in_world (both = x_bar at t = 0).
  std::vector<Eigen::Vector3d> points;
  Motion motion;
  double duration_s = 240.0;

  // A camera of a rig (camera/rig.h; the bench's rig scenarios): the camera sits at rig_from_cam
  // in the rig frame, which parent_from_cam (with `changes`: a change of the whole rig) places in
  // P, so parent_from_cam_c(t) = parent_from_rig(t) * rig_from_cam_c(t). `rig_changes` act on
  // rig_from_cam as `changes` act on parent_from_cam: rpy_deg turns the camera about its own
  // centre and the rig frame's z, y, x axes, x_m shifts its centre in the rig frame, and their
  // intrinsic deltas add to this camera's intrinsics. Without rig_from_cam (a single camera)
  // parent_from_cam is the camera's, and rig_changes must be empty.
  std::optional<Rigid3> rig_from_cam;
  std::vector<CalibrationChange> rig_changes;

  // Whether the calibration changes over time (changes or rig_changes).
  bool HasChanges() const { return !changes.empty() || !rig_changes.empty(); }
  // At t = 0 without changes (a rig camera: parent_from_cam * rig_from_cam).
  Rigid3 CamFromParent() const {
    return rig_from_cam ? (parent_from_cam * *rig_from_cam).Inverse() : parent_from_cam.Inverse();
  }
  // The calibration at time t, with every change applied (the t = 0 one without changes).
  CameraIntrinsics IntrinsicsAt(double t_s) const;
  Rigid3 ParentFromCamAt(double t_s) const;
  Rigid3 CamFromParentAt(double t_s) const { return ParentFromCamAt(t_s).Inverse(); }
  CameraSpec CameraAt(double t_s) const;
  // Times at which the calibration jumps or starts / stops changing (step times, ramp ends),
  // inside (0, duration_s): where a continuous measurement stream has its breakpoints.
  std::vector<double> ChangeTimes() const;
  // Where the points frame (body for a fixed camera, world for a moving one) is in P at time t.
  Rigid3 ParentFromPoints(double t) const;
  // x_bar_i(t) without its homogeneous 1: point i in the parent frame P at time t.
  Eigen::Vector3d PointInParent(int i, double t) const;
  // All points at time t (x_bar in P, and their exact pixels through the calibration at t).
  // Returns false, naming the point, when a point is not in front of the camera.
  bool Observe(double t, std::vector<Eigen::Vector3d>* points_in_parent,
               std::vector<Eigen::Vector2d>* pixels, std::string* why) const;

  // Valid intrinsics, an orthonormal R_C (det +1 unless allow_improper_rotation), at least one
  // point, a positive duration and a valid twist profile.
  bool Check(std::string* why) const;
};

}  // namespace calibench
