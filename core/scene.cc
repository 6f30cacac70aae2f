#include "core/scene.h"

#include <cmath>
#include <sstream>

namespace calibench {

const char* ToString(CalibrationCase c) {
  return c == CalibrationCase::kFixedCamera ? "fixed_camera" : "moving_camera";
}

bool operator==(const CameraSpec& a, const CameraSpec& b) {
  return a.intrinsics == b.intrinsics && a.r_c == b.r_c && a.x_c == b.x_c &&
         a.allow_improper_rotation == b.allow_improper_rotation;
}

Rigid3 SceneTruth::ParentFromPoints(double t) const {
  const Rigid3 world_from_body = motion.WorldFromBody(t);
  return calibration_case == CalibrationCase::kFixedCamera ? world_from_body
                                                           : world_from_body.Inverse();
}

Eigen::Vector3d SceneTruth::PointInParent(int i, double t) const {
  return ParentFromPoints(t) * points[i];
}

bool SceneTruth::Observe(double t, std::vector<Eigen::Vector3d>* points_in_parent,
                         std::vector<Eigen::Vector2d>* pixels, std::string* why) const {
  const Rigid3 parent_from_points = ParentFromPoints(t);
  const Rigid3 cam_from_parent = CamFromParent();
  const std::array<double, 10> params = intrinsics.Params();
  points_in_parent->resize(points.size());
  pixels->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    (*points_in_parent)[i] = parent_from_points * points[i];
    const Eigen::Vector3d point_in_cam = cam_from_parent * (*points_in_parent)[i];
    if (!PinholeSkewCamera::Project(params.data(), point_in_cam.data(), (*pixels)[i].data())) {
      if (why) {
        std::ostringstream msg;
        msg << "feature point " << i << " is behind the camera at t = " << t << " s (depth "
            << point_in_cam.z() << " m)";
        *why = msg.str();
      }
      return false;
    }
  }
  return true;
}

bool SceneTruth::Check(std::string* why) const {
  std::string reason;
  if (!intrinsics.Check(&reason)) {
    if (why) *why = "camera intrinsics: " + reason;
    return false;
  }
  if (!CheckRotation(parent_from_cam.rotation, 1e-9, allow_improper_rotation, &reason)) {
    if (why) *why = "R_C: " + reason;
    return false;
  }
  if (!parent_from_cam.translation.allFinite()) {
    if (why) *why = "x_C must be finite";
    return false;
  }
  if (points.empty()) {
    if (why) *why = "at least one feature point is needed";
    return false;
  }
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      if (why) *why = "feature point " + std::to_string(i) + " is not finite";
      return false;
    }
  }
  if (!(duration_s > 0 && std::isfinite(duration_s))) {
    if (why) *why = "duration_s must be positive";
    return false;
  }
  if (!motion.profile().Check(&reason)) {
    if (why) *why = "motion: " + reason;
    return false;
  }
  return true;
}

}  // namespace calibench
