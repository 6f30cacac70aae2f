#include "batch/zhang.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "batch/board_pose.h"
#include "util/opencv_threads.h"

namespace calibench {

bool ZhangOptions::Check(std::string* why) const {
  std::string msg;
  if (image_width <= 0 || image_height <= 0) msg = "image size must be positive";
  if (view_stride < 1) msg = "view_stride must be >= 1";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

namespace {

Rigid3 PoseFromRodrigues(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  Rigid3 pose;
  cv::cv2eigen(r, pose.rotation);
  for (int i = 0; i < 3; ++i) pose.translation[i] = tvec.at<double>(i);
  return pose;
}

// The equidistant lens through cv::fisheye::calibrate (OpenCV's Kannala-Brandt k1..k4; its own
// initialisation: f from the image size, c at the centre, extrinsics from homographies). It
// reports no standard deviations; the per-point RMS is recomputed with our projection on the used
// views (result->used_views indexes planar_views).
ZhangResult CalibrateFisheye(const std::vector<View>& planar_views,
                             const std::vector<std::vector<cv::Point3f>>& object_points,
                             const std::vector<std::vector<cv::Point2f>>& image_points,
                             const ZhangOptions& options, ZhangResult* result,
                             const SummaryClock& clock) {
  auto finish = [&](MethodStatus status, const std::string& message) {
    return clock.Finish(result, status, message);
  };
  UseSequentialOpenCv();
  cv::Matx33d camera_matrix = cv::Matx33d::eye();
  cv::Vec4d dist(0, 0, 0, 0);
  std::vector<cv::Mat> rvecs, tvecs;
  const int flags = cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW;
  try {
    cv::fisheye::calibrate(
        object_points, image_points, cv::Size(options.image_width, options.image_height),
        camera_matrix, dist, rvecs, tvecs, flags,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
  } catch (const cv::Exception& e) {
    return finish(MethodStatus::kFailed, std::string("cv::fisheye::calibrate: ") + e.what());
  }
  CameraIntrinsics& k = result->intrinsics;
  k = CameraIntrinsics();
  k.family = LensFamily::kEquidistant;
  k.fku_px = camera_matrix(0, 0);
  k.fkv_px = camera_matrix(1, 1);
  k.u0_px = camera_matrix(0, 2);
  k.v0_px = camera_matrix(1, 2);
  k.k1 = dist[0], k.k2 = dist[1], k.k3 = dist[2], k.k4 = dist[3];
  // cv::fisheye keeps the pose of its homography initialisation for a view that LM cannot move
  // (seen: a partial board at 70 degrees off axis, 84 px RMS). Each view keeps the better of
  // OpenCV's pose and the PnP pose through the estimated lens (batch/board_pose.h).
  double sum_sq = 0.0;
  long count = 0;
  for (size_t v = 0; v < rvecs.size(); ++v) {
    const View& view = planar_views[result->used_views[v]];
    Rigid3 pose = PoseFromRodrigues(rvecs[v], tvecs[v]), pnp;
    double sq = 0.0, pnp_sq = 0.0;
    ViewSquaredErrorPx2(view, k, pose, &sq);  // +inf when a point is behind the camera.
    if (BoardPoseFromIntrinsics(view, k, &pnp, nullptr) &&
        ViewSquaredErrorPx2(view, k, pnp, &pnp_sq) && pnp_sq < sq) {
      pose = pnp;
      sq = pnp_sq;
    }
    if (!std::isfinite(sq)) {
      return finish(MethodStatus::kFailed, "cv::fisheye::calibrate: view " +
                                               std::to_string(result->used_views[v]) +
                                               " has points behind the camera at its pose");
    }
    result->cam_from_board.push_back(pose);
    sum_sq += sq;
    count += static_cast<long>(view.points.size());
  }
  if (count == 0) return finish(MethodStatus::kFailed, "cv::fisheye::calibrate: no point projects");
  result->rms_reproj_px = std::sqrt(sum_sq / count);
  return finish(MethodStatus::kOk,
                "cv::fisheye::calibrate (equidistant); OpenCV fixes the skew: phi reported as 90 "
                "deg");
}

// Every stride-th view with at least 4 points as OpenCV's float point lists; *used_views gets
// their indices. False with *why when a point is off the board plane z = 0.
bool OpenCvPoints(const std::vector<View>& views, int stride,
                  std::vector<std::vector<cv::Point3f>>* object_points,
                  std::vector<std::vector<cv::Point2f>>* image_points, std::vector<int>* used_views,
                  std::string* why) {
  for (size_t v = 0; v < views.size(); v += stride) {
    const View& view = views[v];
    if (view.points.size() < 4) continue;
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    for (size_t i = 0; i < view.points.size(); ++i) {
      if (std::abs(view.points[i].z()) > 1e-9) {
        *why = "zhang needs planar targets: view " + std::to_string(v) + " has a point off z = 0";
        return false;
      }
      obj.emplace_back(view.points[i].x(), view.points[i].y(), 0.f);
      img.emplace_back(view.pixels[i].x(), view.pixels[i].y());
    }
    object_points->push_back(std::move(obj));
    image_points->push_back(std::move(img));
    used_views->push_back(static_cast<int>(v));
  }
  return true;
}

// cv::calibrateCamera's flags for a radtan `model` (the equidistant family goes to cv::fisheye).
// False with *why for the omnidirectional families, which OpenCV cannot start.
bool OpenCvFlags(LensModel model, int* flags, std::string* why) {
  const LensFamily family = FamilyOf(model);
  if (!InfoOf(family).zhang_starts) {
    std::string starts;  // The families with LensFamilyInfo::zhang_starts: radtan and equidistant.
    for (const LensFamilyInfo& info : LensFamilies()) {
      if (info.zhang_starts) starts += (starts.empty() ? "" : " and ") + std::string(info.name);
    }
    *why = std::string("zhang: OpenCV has no initialisation for the ") + ToString(model) +
           " lens model (" + starts + " only); the wide start (batch/wide_init.h) starts it";
    return false;
  }
  if (family != LensFamily::kRadTan) return true;  // Equidistant: cv::fisheye (CalibrateFisheye).
  // The radtan coefficients the model keeps at 0 (slots 5 k1, 6 k2, 7 p1, 8 p2, 9 k3).
  const std::vector<int> fixed = FixedIntrinsics(model, /*estimate_skew=*/true);
  const auto is_fixed = [&](int slot) {
    return std::find(fixed.begin(), fixed.end(), slot) != fixed.end();
  };
  *flags = 0;
  if (is_fixed(5)) *flags |= cv::CALIB_FIX_K1;
  if (is_fixed(6)) *flags |= cv::CALIB_FIX_K2;
  if (is_fixed(9)) *flags |= cv::CALIB_FIX_K3;
  if (is_fixed(7) && is_fixed(8)) *flags |= cv::CALIB_ZERO_TANGENT_DIST;
  return true;
}

}  // namespace

ZhangResult CalibrateZhang(const std::vector<View>& planar_views, const ZhangOptions& options) {
  const SummaryClock clock;
  ZhangResult result;
  result.intrinsics_std.fill(std::numeric_limits<double>::quiet_NaN());
  auto finish = [&](MethodStatus status, const std::string& message) {
    return clock.Finish(&result, status, message);
  };
  std::string why;
  if (!options.Check(&why)) return finish(MethodStatus::kFailed, "zhang options: " + why);

  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  if (!OpenCvPoints(planar_views, options.view_stride, &object_points, &image_points,
                    &result.used_views, &why)) {
    return finish(MethodStatus::kFailed, why);
  }
  if (object_points.size() < 2) {
    return finish(MethodStatus::kFailed, "zhang needs at least 2 views of the board");
  }
  if (FamilyOf(options.model) == LensFamily::kEquidistant) {
    return CalibrateFisheye(planar_views, object_points, image_points, options, &result, clock);
  }
  int flags = 0;
  if (!OpenCvFlags(options.model, &flags, &why)) return finish(MethodStatus::kFailed, why);
  // LM's normal equations by LU, not OpenCV's default SVD: the SVD of the (6 views + intrinsics)^2
  // matrix at every iteration was 90% of a call (0.4 s on 30 views); the system is positive
  // definite for a calibration that converges, and the solution agrees to ~1e-9 relative.
  flags |= cv::CALIB_USE_LU;
  UseSequentialOpenCv();
  cv::Mat camera_matrix = cv::Mat::eye(3, 3, CV_64F), dist = cv::Mat::zeros(5, 1, CV_64F);
  std::vector<cv::Mat> rvecs, tvecs;
  cv::Mat std_intrinsics, std_extrinsics, per_view_errors;
  try {
    cv::calibrateCamera(object_points, image_points,
                        cv::Size(options.image_width, options.image_height), camera_matrix, dist,
                        rvecs, tvecs, std_intrinsics, std_extrinsics, per_view_errors, flags);
  } catch (const cv::Exception& e) {
    return finish(MethodStatus::kFailed, std::string("cv::calibrateCamera: ") + e.what());
  }
  CameraIntrinsics& k = result.intrinsics;
  k.fku_px = camera_matrix.at<double>(0, 0);
  k.fkv_px = camera_matrix.at<double>(1, 1);
  k.u0_px = camera_matrix.at<double>(0, 2);
  k.v0_px = camera_matrix.at<double>(1, 2);
  k.phi_deg = 90.0;
  k.k1 = dist.at<double>(0);
  k.k2 = dist.at<double>(1);
  k.p1 = dist.at<double>(2);
  k.p2 = dist.at<double>(3);
  k.k3 = dist.at<double>(4);
  // OpenCV's order: fx, fy, cx, cy, k1, k2, p1, p2, k3, ... -> ours (phi at 2 stays NaN).
  const int map[9] = {0, 1, 3, 4, 5, 6, 7, 8, 9};
  const std::vector<int> fixed = FixedIntrinsics(options.model, false);
  for (int i = 0; i < 9; ++i) {
    if (std::find(fixed.begin(), fixed.end(), map[i]) == fixed.end()) {
      result.intrinsics_std[map[i]] = std_intrinsics.at<double>(i);
    }
  }
  double sum_sq = 0.0;
  long count = 0;
  for (size_t v = 0; v < rvecs.size(); ++v) {
    result.cam_from_board.push_back(PoseFromRodrigues(rvecs[v], tvecs[v]));
    const double e = per_view_errors.at<double>(static_cast<int>(v));
    sum_sq += e * e * static_cast<double>(object_points[v].size());
    count += static_cast<long>(object_points[v].size());
  }
  result.rms_reproj_px = std::sqrt(sum_sq / count);
  return finish(MethodStatus::kOk, "OpenCV fixes the skew: phi reported as 90 deg");
}

ZhangResult FromWideStart(const WideInitResult& wide) {
  ZhangResult result;
  static_cast<MethodSummary&>(result) = wide;
  result.intrinsics = wide.intrinsics;
  result.intrinsics_std.fill(std::nan(""));
  result.cam_from_board = wide.cam_from_board;
  result.used_views = wide.used_views;
  result.rms_reproj_px = wide.rms_reproj_px;
  return result;
}

}  // namespace calibench
