#include "batch/stereo_opencv.h"

#include <algorithm>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <tuple>

#include "util/opencv_threads.h"

namespace calibench {

bool StereoOpenCvOptions::Check(std::string* why) const {
  std::string msg;
  const LensFamily family = FamilyOf(model);
  if (family != LensFamily::kRadTan && family != LensFamily::kEquidistant) {
    msg = std::string("OpenCV's stereo calibration has no ") + ToString(model) +
          " lens model (radtan models: cv::stereoCalibrate; pinhole-equi: "
          "cv::fisheye::stereoCalibrate)";
  } else if (max_iterations < 1) {
    msg = "max_iterations must be >= 1";
  }
  if (msg.empty()) return true;
  if (why != nullptr) *why = msg;
  return false;
}

namespace {

using Key = std::tuple<double, double, double>;

// The frame's corners when both views hold the same ones (header comment): object points in
// camera 0's order and both images' pixels; false otherwise.
bool WholeInBoth(const RigFrame& frame, std::vector<cv::Point3d>* object,
                 std::vector<cv::Point2d>* image0, std::vector<cv::Point2d>* image1) {
  const View& a = frame.views_by_camera[0];
  const View& b = frame.views_by_camera[1];
  if (a.points.size() < 4 || a.points.size() != b.points.size()) return false;
  std::map<Key, size_t> in_b;
  for (size_t j = 0; j < b.points.size(); ++j) {
    in_b[{b.points[j].x(), b.points[j].y(), b.points[j].z()}] = j;
  }
  for (size_t i = 0; i < a.points.size(); ++i) {
    const auto it = in_b.find({a.points[i].x(), a.points[i].y(), a.points[i].z()});
    if (it == in_b.end()) return false;
    object->emplace_back(a.points[i].x(), a.points[i].y(), a.points[i].z());
    image0->emplace_back(a.pixels[i].x(), a.pixels[i].y());
    image1->emplace_back(b.pixels[it->second].x(), b.pixels[it->second].y());
  }
  return true;
}

cv::Matx33d CameraMatrix(const CameraIntrinsics& k) {
  return cv::Matx33d(k.fku_px, 0, k.u0_px, 0, k.fkv_px, k.v0_px, 0, 0, 1);
}

// The start's radtan coefficients (k1, k2, p1, p2, k3), those the model fixes at 0.
cv::Mat RadTanCoefficients(const CameraIntrinsics& k, LensModel model) {
  const std::vector<int> fixed = FixedIntrinsics(model, false);
  const double values[5] = {k.k1, k.k2, k.p1, k.p2, k.k3};
  cv::Mat dist = cv::Mat::zeros(5, 1, CV_64F);
  for (int i = 0; i < 5; ++i) {
    if (std::find(fixed.begin(), fixed.end(), 5 + i) == fixed.end()) dist.at<double>(i) = values[i];
  }
  return dist;
}

// cv::calibrateCamera's flags for the radtan coefficients `model` keeps at 0 (batch/zhang.cc).
int RadTanFlags(LensModel model) {
  const std::vector<int> fixed = FixedIntrinsics(model, false);
  const auto is_fixed = [&](int slot) {
    return std::find(fixed.begin(), fixed.end(), slot) != fixed.end();
  };
  int flags = 0;
  if (is_fixed(5)) flags |= cv::CALIB_FIX_K1;
  if (is_fixed(6)) flags |= cv::CALIB_FIX_K2;
  if (is_fixed(9)) flags |= cv::CALIB_FIX_K3;
  if (is_fixed(7) && is_fixed(8)) flags |= cv::CALIB_ZERO_TANGENT_DIST;
  return flags;
}

CameraIntrinsics FromOpenCv(const cv::Matx33d& k, const cv::Mat& dist, LensFamily family) {
  CameraIntrinsics out;
  out.family = family;
  out.fku_px = k(0, 0), out.fkv_px = k(1, 1), out.u0_px = k(0, 2), out.v0_px = k(1, 2);
  out.phi_deg = 90.0;
  if (family == LensFamily::kRadTan) {
    out.k1 = dist.at<double>(0), out.k2 = dist.at<double>(1);
    out.p1 = dist.at<double>(2), out.p2 = dist.at<double>(3), out.k3 = dist.at<double>(4);
  } else {
    out.k1 = dist.at<double>(0), out.k2 = dist.at<double>(1);
    out.k3 = dist.at<double>(2), out.k4 = dist.at<double>(3);
  }
  return out;
}

}  // namespace

StereoOpenCvResult CalibrateStereoOpenCv(const std::vector<RigFrame>& frames,
                                         const CameraRig& initial,
                                         const StereoOpenCvOptions& options) {
  const SummaryClock clock;
  StereoOpenCvResult result;
  const auto finish = [&](MethodStatus status, const std::string& message) {
    return clock.Finish(&result, status, message);
  };
  std::string why;
  if (!options.Check(&why)) return finish(MethodStatus::kFailed, "stereo opencv options: " + why);
  if (initial.NumCameras() != 2) {
    return finish(MethodStatus::kFailed,
                  "stereo opencv: OpenCV calibrates two cameras, the rig has " +
                      std::to_string(initial.NumCameras()));
  }
  const LensFamily family = FamilyOf(options.model);
  for (int c = 0; c < 2; ++c) {
    const RigCamera& camera = initial.cameras[c];
    if (!camera.intrinsics.Check(&why)) {
      return finish(MethodStatus::kFailed,
                    "stereo opencv: camera " + std::to_string(c) + " intrinsics: " + why);
    }
    if (camera.intrinsics.family != family) {
      return finish(MethodStatus::kFailed, "stereo opencv: camera " + std::to_string(c) +
                                               "'s intrinsics are " +
                                               ToString(camera.intrinsics.family) + ", the model " +
                                               ToString(options.model) + " is " + ToString(family));
    }
  }
  if (initial.cameras[0].image_width <= 0) {
    return finish(MethodStatus::kFailed, "stereo opencv: camera 0 needs its image size");
  }
  std::vector<std::vector<cv::Point3d>> object_points;
  std::vector<std::vector<cv::Point2d>> image_points0, image_points1;
  for (size_t f = 0; f < frames.size(); ++f) {
    if (frames[f].views_by_camera.size() != 2) {
      return finish(MethodStatus::kFailed,
                    "stereo opencv: frame " + std::to_string(f) + " does not hold two views");
    }
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image0, image1;
    if (!WholeInBoth(frames[f], &object, &image0, &image1)) continue;
    object_points.push_back(std::move(object));
    image_points0.push_back(std::move(image0));
    image_points1.push_back(std::move(image1));
    result.used_frames.push_back(static_cast<int>(f));
    result.num_points += static_cast<int>(object_points.back().size());
  }
  if (object_points.size() < 2) {
    return finish(MethodStatus::kFailed,
                  "stereo opencv: fewer than 2 frames that both cameras saw whole");
  }
  const cv::Size image_size(initial.cameras[0].image_width, initial.cameras[0].image_height);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS,
                                  options.max_iterations, 1e-12);
  cv::Matx33d k0 = CameraMatrix(initial.cameras[0].intrinsics);
  cv::Matx33d k1 = CameraMatrix(initial.cameras[1].intrinsics);
  cv::Mat d0, d1, r, t;
  UseSequentialOpenCv();
  try {
    if (family == LensFamily::kRadTan) {
      d0 = RadTanCoefficients(initial.cameras[0].intrinsics, options.model);
      d1 = RadTanCoefficients(initial.cameras[1].intrinsics, options.model);
      const int flags =
          RadTanFlags(options.model) |
          (options.fix_intrinsics ? cv::CALIB_FIX_INTRINSIC : cv::CALIB_USE_INTRINSIC_GUESS);
      // cv::stereoCalibrate takes float points only (cv::fisheye takes doubles).
      std::vector<std::vector<cv::Point3f>> object_f(object_points.size());
      std::vector<std::vector<cv::Point2f>> image0_f(object_points.size()),
          image1_f(object_points.size());
      for (size_t f = 0; f < object_points.size(); ++f) {
        for (size_t i = 0; i < object_points[f].size(); ++i) {
          object_f[f].emplace_back(object_points[f][i]);
          image0_f[f].emplace_back(image_points0[f][i]);
          image1_f[f].emplace_back(image_points1[f][i]);
        }
      }
      cv::Mat e, f;
      result.rms_reproj_px = cv::stereoCalibrate(object_f, image0_f, image1_f, k0, d0, k1, d1,
                                                 image_size, r, t, e, f, flags, criteria);
    } else {
      const auto coefficients = [](const CameraIntrinsics& k) {
        return cv::Mat((cv::Mat_<double>(4, 1) << k.k1, k.k2, k.k3, k.k4));
      };
      d0 = coefficients(initial.cameras[0].intrinsics);
      d1 = coefficients(initial.cameras[1].intrinsics);
      const int flags = cv::fisheye::CALIB_FIX_SKEW |
                        (options.fix_intrinsics ? cv::fisheye::CALIB_FIX_INTRINSIC
                                                : cv::fisheye::CALIB_USE_INTRINSIC_GUESS);
      result.rms_reproj_px =
          cv::fisheye::stereoCalibrate(object_points, image_points0, image_points1, k0, d0, k1, d1,
                                       image_size, r, t, flags, criteria);
    }
  } catch (const cv::Exception& e) {
    return finish(MethodStatus::kFailed, std::string("stereo opencv: ") + e.what());
  }
  result.rig = initial;
  result.rig.cameras[0].intrinsics = FromOpenCv(k0, d0, family);
  result.rig.cameras[1].intrinsics = FromOpenCv(k1, d1, family);
  for (RigCamera& camera : result.rig.cameras) camera.lens_model = options.model;
  result.rig.cameras[0].cam_from_rig = Rigid3();
  Rigid3& pose = result.rig.cameras[1].cam_from_rig;
  cv::Mat r64, t64;
  r.convertTo(r64, CV_64F);
  t.convertTo(t64, CV_64F);
  cv::cv2eigen(r64, pose.rotation);
  for (int i = 0; i < 3; ++i) pose.translation[i] = t64.at<double>(i);
  if (!result.rig.Check(&why)) return finish(MethodStatus::kFailed, "stereo opencv: " + why);
  const int skipped = static_cast<int>(frames.size() - result.used_frames.size());
  return finish(MethodStatus::kOk,
                std::string(family == LensFamily::kRadTan ? "cv::stereoCalibrate"
                                                          : "cv::fisheye::stereoCalibrate") +
                    " on " + std::to_string(result.used_frames.size()) + " frames (" +
                    std::to_string(skipped) +
                    " skipped: not seen whole by both); OpenCV fixes the skew (phi 90 deg)");
}

}  // namespace calibench
