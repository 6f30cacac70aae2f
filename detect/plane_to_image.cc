#include "detect/plane_to_image.h"

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

namespace calibench {

bool PlaneToImage::Fit(const CameraIntrinsics* camera, const std::vector<Eigen::Vector2d>& on_plane,
                       const std::vector<Eigen::Vector2d>& pixels) {
  camera_ = camera && camera->IsDistorted() ? camera : nullptr;
  if (on_plane.size() < 4 || on_plane.size() != pixels.size()) return false;
  std::vector<cv::Point2d> from, to;
  if (camera_) {
    std::vector<Eigen::Vector3d> rays(pixels.size());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < pixels.size(); ++i) {
      if (!UnprojectToRay(*camera_, pixels[i], &rays[i])) return false;
      sum += rays[i];
    }
    if (!TangentPlane::About(sum, &plane_)) return false;
    for (const Eigen::Vector3d& ray : rays) {
      Eigen::Vector2d q;
      if (!plane_.FromRay(ray, &q)) return false;
      to.emplace_back(q.x(), q.y());
    }
  } else {
    for (const Eigen::Vector2d& p : pixels) to.emplace_back(p.x(), p.y());
  }
  for (const Eigen::Vector2d& p : on_plane) from.emplace_back(p.x(), p.y());
  cv::Mat h;
  if (from.size() == 4) {  // getPerspectiveTransform takes float points only.
    const std::vector<cv::Point2f> from_f(from.begin(), from.end()), to_f(to.begin(), to.end());
    h = cv::getPerspectiveTransform(from_f, to_f);
  } else {
    h = cv::findHomography(from, to, 0);
  }
  if (h.empty()) return false;
  cv::cv2eigen(h, to_image_);
  if (!to_image_.allFinite()) return false;
  w_sign_ = (to_image_ * Eigen::Vector3d(from[0].x, from[0].y, 1)).z() > 0 ? 1 : -1;
  return true;
}

bool PlaneToImage::operator()(const Eigen::Vector2d& on_plane, Eigen::Vector2d* pixel) const {
  const Eigen::Vector3d h = w_sign_ * (to_image_ * on_plane.homogeneous());
  if (camera_) return ProjectPoint(*camera_, plane_.ToRayHomogeneous(h), pixel);
  if (!(h.z() > 0)) return false;
  *pixel = h.hnormalized();
  return true;
}

}  // namespace calibench
