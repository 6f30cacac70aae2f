#include "batch/board_pose.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
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
                             Rigid3* cam_from_board, std::string* why,
                             const BoardPoseOptions& options) {
  std::vector<Eigen::Vector3d> rays(view.pixels.size());
  for (size_t i = 0; i < view.pixels.size(); ++i) {
    if (!UnprojectToRay(intrinsics, view.pixels[i], &rays[i])) {
      if (why) *why = "pixel " + std::to_string(i) + " lies outside the lens model's valid region";
      return false;
    }
  }
  return BoardPoseFromRays(view, rays, cam_from_board, why, options);
}

namespace {

// The points must not be collinear, nor all but one of them (see the header comment); all finite.
bool PointsFixAPose(const std::vector<Eigen::Vector3d>& points, std::string* why) {
  const size_t n = points.size();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite()) {
      if (why) *why = "point " + std::to_string(i) + " is not finite";
      return false;
    }
    centroid += points[i] / static_cast<double>(n);
  }
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - centroid) * (p - centroid).transpose();
  // Collinear when sqrt(l1 / l2) <= kMinPointSpreadRatio for scatter - w d d^T (w d d^T: the
  // downdate that takes a point d - centroid out of the set).
  const auto collinear = [&scatter](const Eigen::Vector3d& d, double w) {
    const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(
                                       scatter - w * d * d.transpose(), Eigen::EigenvaluesOnly)
                                       .eigenvalues();
    return !(spread[1] > kMinPointSpreadRatio * kMinPointSpreadRatio * spread[2]);
  };
  if (collinear(Eigen::Vector3d::Zero(), 0.0)) {
    if (why) *why = "the points are collinear: the pose is not determined";
    return false;
  }
  const double w = static_cast<double>(n) / static_cast<double>(n - 1);
  for (size_t k = 0; k < n; ++k) {
    if (collinear(points[k] - centroid, w)) {
      if (why) {
        *why = "all the points but point " + std::to_string(k) +
               " are collinear: the pose is not determined";
      }
      return false;
    }
  }
  return true;
}

// cv::solvePnP (IPPE for a planar board, else iterative; then LM when `refine`) on normalised
// coordinates (K = I, no distortion). False (and *why) when OpenCV finds no finite pose.
bool SolvePnpNormalised(const std::vector<cv::Point3d>& object,
                        const std::vector<cv::Point2d>& normalised, bool planar, bool refine,
                        Rigid3* cam_from_board, std::string* why) {
  const cv::Mat k = cv::Mat::eye(3, 3, CV_64F), no_distortion;
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, normalised, k, no_distortion, rvec, tvec, false,
                      planar ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_ITERATIVE)) {
      if (why) *why = "cv::solvePnP found no pose";
      return false;
    }
    if (refine) cv::solvePnPRefineLM(object, normalised, k, no_distortion, rvec, tvec);
  } catch (const cv::Exception& e) {
    if (why) *why = std::string("cv::solvePnP: ") + e.what();
    return false;
  }
  if (!(cv::checkRange(rvec) && cv::checkRange(tvec))) {
    if (why) *why = "cv::solvePnP returned a non-finite pose";
    return false;
  }
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  cv::cv2eigen(r, cam_from_board->rotation);
  cam_from_board->translation =
      Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return true;
}

}  // namespace

bool BoardPoseFromRays(const View& view, const std::vector<Eigen::Vector3d>& rays,
                       Rigid3* cam_from_board, std::string* why, const BoardPoseOptions& options) {
  const size_t n = view.points.size();
  bool planar = true;
  for (const Eigen::Vector3d& p : view.points) planar &= std::abs(p.z()) < 1e-9;
  if (n < (planar ? 4u : 6u) || rays.size() != n) {
    if (why) *why = "a pose needs at least " + std::string(planar ? "4" : "6") + " points";
    return false;
  }
  if (!PointsFixAPose(view.points, why)) return false;
  // Q: the mean ray to the axis.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& r : rays) mean += r.normalized();
  const double min_cos = std::cos(0.5 * kMaxBoardSpanDeg * M_PI / 180.0);
  if (!(mean.norm() > min_cos * static_cast<double>(n))) {
    if (why) *why = "the board's rays span more than " + std::to_string(kMaxBoardSpanDeg) + " deg";
    return false;
  }
  const Eigen::Matrix3d q =
      Eigen::Quaterniond::FromTwoVectors(mean, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> normalised;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d turned = q * rays[i].normalized();
    if (!(turned.z() > min_cos)) {
      if (why)
        *why = "the board's rays span more than " + std::to_string(kMaxBoardSpanDeg) + " deg";
      return false;
    }
    object.emplace_back(view.points[i].x(), view.points[i].y(), view.points[i].z());
    normalised.emplace_back(turned.x() / turned.z(), turned.y() / turned.z());
  }
  Rigid3 turned_from_board;
  if (!SolvePnpNormalised(object, normalised, planar, options.refine, &turned_from_board, why)) {
    return false;
  }
  cam_from_board->rotation = q.transpose() * turned_from_board.rotation;
  cam_from_board->translation = q.transpose() * turned_from_board.translation;
  return true;
}

}  // namespace calibench
