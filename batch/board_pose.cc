#include "batch/board_pose.h"

#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace calibench {

bool ViewSquaredErrorPx2(const View& view, const CameraIntrinsics& intrinsics,
                         const Rigid3& cam_from_board, double* sum_sq_px2) {
  double sum = 0.0;
  for (size_t i = 0; i < view.points.size(); ++i) {
    Eigen::Vector2d pixel;
    if (!ProjectPoint(intrinsics, cam_from_board * view.points[i], &pixel)) {
      *sum_sq_px2 = std::numeric_limits<double>::infinity();
      return false;
    }
    sum += (pixel - view.pixels[i]).squaredNorm();
  }
  *sum_sq_px2 = sum;
  return true;
}

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

bool FocalScanOptions::Check(std::string* why) const {
  std::string msg;
  if (image_width <= 0 || image_height <= 0) msg = "image size must be positive";
  if (!(min_focal_per_width > 0 && max_focal_per_width > min_focal_per_width)) {
    msg = "focal range must satisfy 0 < min < max";
  }
  if (steps < 2) msg = "steps must be >= 2";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

bool EquidistantFocalScan(const std::vector<View>& views, const FocalScanOptions& options,
                          FocalScanResult* result, std::string* why) {
  if (!options.Check(why)) return false;
  *result = FocalScanResult();
  double best = std::numeric_limits<double>::infinity();
  const double w = options.image_width;
  for (int s = 0; s < options.steps; ++s) {
    const double f = w * options.min_focal_per_width *
                     std::pow(options.max_focal_per_width / options.min_focal_per_width,
                              static_cast<double>(s) / (options.steps - 1));
    CameraIntrinsics k;
    k.family = LensFamily::kEquidistant;
    k.fku_px = k.fkv_px = f;
    k.u0_px = 0.5 * (options.image_width - 1);
    k.v0_px = 0.5 * (options.image_height - 1);
    // Every view must be posed, all its points in front; among those f, the least RMS.
    std::vector<Rigid3> poses(views.size());
    double sum_sq = 0.0;
    long count = 0;
    int posed = 0;
    for (size_t v = 0; v < views.size(); ++v) {
      double view_sq = 0.0;
      if (!BoardPoseFromIntrinsics(views[v], k, &poses[v], nullptr) ||
          !ViewSquaredErrorPx2(views[v], k, poses[v], &view_sq)) {
        break;
      }
      ++posed;
      sum_sq += view_sq;
      count += static_cast<long>(views[v].points.size());
    }
    const double rms = count > 0 ? std::sqrt(sum_sq / count) : best;
    if (posed == static_cast<int>(views.size()) && rms < best) {
      best = rms;
      result->intrinsics = k;
      result->cam_from_board = poses;
      result->rms_reproj_px = rms;
      result->views_posed = posed;
    }
  }
  if (!std::isfinite(best)) {
    if (why) *why = "no focal length of the scan poses every view";
    return false;
  }
  return true;
}

}  // namespace calibench
