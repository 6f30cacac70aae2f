// ComputeEpipolarErrors (batch/rig_refine.h): the epipolar error of the corners two cameras of a
// rig saw in the same frame.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "batch/rig_refine.h"

namespace calibench {

EpipolarErrors ComputeEpipolarErrors(const std::vector<RigFrame>& frames, const CameraRig& rig,
                                     int camera_a, int camera_b) {
  EpipolarErrors out;
  out.camera_a = camera_a;
  out.camera_b = camera_b;
  if (camera_a < 0 || camera_b < 0 || camera_a >= rig.NumCameras() ||
      camera_b >= rig.NumCameras() || camera_a == camera_b) {
    return out;  // No pair: no corner.
  }
  const Rigid3 a_from_b = rig.CamFromCam(camera_a, camera_b);
  const CameraIntrinsics& ka = rig.cameras[camera_a].intrinsics;
  const CameraIntrinsics& kb = rig.cameras[camera_b].intrinsics;
  double total_sq = 0;
  for (const RigFrame& frame : frames) {
    if (static_cast<int>(frame.views_by_camera.size()) != rig.NumCameras()) {
      out.frame_rms_px.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const View& va = frame.views_by_camera[camera_a];
    const View& vb = frame.views_by_camera[camera_b];
    std::map<std::tuple<double, double, double>, size_t> in_a;
    for (size_t i = 0; i < va.points.size(); ++i) {
      in_a[{va.points[i].x(), va.points[i].y(), va.points[i].z()}] = i;
    }
    double frame_sq = 0;
    int frame_points = 0;
    for (size_t j = 0; j < vb.points.size(); ++j) {
      const auto it = in_a.find({vb.points[j].x(), vb.points[j].y(), vb.points[j].z()});
      if (it == in_a.end()) continue;
      Eigen::Vector3d ray_a, ray_b;
      if (!UnprojectToRay(ka, va.pixels[it->second], &ray_a) ||
          !UnprojectToRay(kb, vb.pixels[j], &ray_b)) {
        continue;
      }
      // The epipolar plane through both centres and the other camera's ray, in each camera.
      const Eigen::Vector3d ray_b_in_a = a_from_b.rotation * ray_b;
      const Eigen::Vector3d normal_a = a_from_b.translation.cross(ray_b_in_a).normalized();
      const Eigen::Vector3d normal_b =
          (a_from_b.rotation.transpose() * ray_a.cross(a_from_b.translation)).normalized();
      const double angle_a = std::asin(std::min(1.0, std::abs(normal_a.dot(ray_a.normalized()))));
      const double angle_b = std::asin(std::min(1.0, std::abs(normal_b.dot(ray_b.normalized()))));
      const double error_px = 0.5 * (angle_a * ka.fku_px + angle_b * kb.fku_px);
      frame_sq += error_px * error_px;
      ++frame_points;
    }
    out.frame_rms_px.push_back(frame_points > 0 ? std::sqrt(frame_sq / frame_points)
                                                : std::numeric_limits<double>::quiet_NaN());
    total_sq += frame_sq;
    out.num_points += frame_points;
  }
  out.rms_px = out.num_points > 0 ? std::sqrt(total_sq / out.num_points) : 0.0;
  return out;
}

}  // namespace calibench
