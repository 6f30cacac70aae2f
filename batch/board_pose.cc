#include "batch/board_pose.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace calibench {

bool BoardPoseFromIntrinsics(const View& view, const CameraIntrinsics& intrinsics,
                             Rigid3* cam_from_board, std::string* why) {
  const size_t n = view.points.size();
  bool planar = true;
  for (const Eigen::Vector3d& p : view.points) planar &= std::abs(p.z()) < 1e-9;
  if (n < (planar ? 4u : 6u)) {
    if (why) *why = "a pose needs at least " + std::string(planar ? "4" : "6") + " points";
    return false;
  }
  const Eigen::Matrix3d a_inv = intrinsics.Matrix().inverse();
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> normalised;
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector2d xy;
    const Eigen::Vector2d distorted = (a_inv * view.pixels[i].homogeneous()).head<2>();
    if (!UndistortNormalized(intrinsics, distorted, &xy)) {
      if (why) *why = "pixel " + std::to_string(i) + " lies outside the lens model's valid region";
      return false;
    }
    object.emplace_back(view.points[i].x(), view.points[i].y(), view.points[i].z());
    normalised.emplace_back(xy.x(), xy.y());
  }
  const cv::Mat k = cv::Mat::eye(3, 3, CV_64F), no_distortion;
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, normalised, k, no_distortion, rvec, tvec, false,
                      planar ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_ITERATIVE)) {
      if (why) *why = "cv::solvePnP found no pose";
      return false;
    }
    cv::solvePnPRefineLM(object, normalised, k, no_distortion, rvec, tvec);
  } catch (const cv::Exception& e) {
    if (why) *why = std::string("cv::solvePnP: ") + e.what();
    return false;
  }
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  cv::cv2eigen(r, cam_from_board->rotation);
  for (int i = 0; i < 3; ++i) cam_from_board->translation[i] = tvec.at<double>(i);
  return true;
}

}  // namespace calibench
