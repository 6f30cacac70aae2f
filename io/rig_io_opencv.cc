// The OpenCV stereo file of a 2-camera rig (rig_io.h), in the names of OpenCV's stereo_calib.cpp.
#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "calib/rectify.h"
#include "io/camera_io_formats.h"
#include "io/rig_io_formats.h"

namespace calibench {
namespace rig_io_internal {

using camera_io_internal::Fail;

namespace {

// The field names of camera i (1 or 2): the sample's M1 D1, the rest with the suffix _i.
camera_io_internal::OpenCvFieldName StereoNames(int i) {
  return [i](const std::string& field) {
    if (field == "camera_matrix") return "M" + std::to_string(i);
    if (field == "distortion_coefficients") return "D" + std::to_string(i);
    return field + "_" + std::to_string(i);
  };
}

template <int R, int C>
cv::Mat ToMat(const Eigen::Matrix<double, R, C>& m) {
  cv::Mat out(R, C, CV_64F);
  for (int r = 0; r < R; ++r) {
    for (int c = 0; c < C; ++c) out.at<double>(r, c) = m(r, c);
  }
  return out;
}

// The distortion coefficients OpenCV's functions take for camera k (radtan: 5, equidistant: 4).
cv::Mat OpenCvDistortion(const CameraIntrinsics& k) {
  if (k.family == LensFamily::kEquidistant) {
    return (cv::Mat_<double>(1, 4) << k.k1, k.k2, k.k3, k.k4);
  }
  return (cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3);
}

// R1 R2 P1 P2 Q of the pair (rig_io.h) and the name of who computed them; false (and *why) when
// calibench's rectification fails.
bool Rectify(const CameraRig& rig, cv::Mat* r1, cv::Mat* r2, cv::Mat* p1, cv::Mat* p2, cv::Mat* q,
             std::string* method, std::string* why) {
  const CameraIntrinsics& a = rig.cameras[0].intrinsics;
  const CameraIntrinsics& b = rig.cameras[1].intrinsics;
  const cv::Size size(rig.cameras[0].image_width, rig.cameras[0].image_height);
  const Rigid3& pose = rig.cameras[1].cam_from_rig;
  const cv::Mat m1 = ToMat(a.Matrix()), m2 = ToMat(b.Matrix());
  const cv::Mat r = ToMat(pose.rotation), t = ToMat<3, 1>(pose.translation);
  if (a.family == LensFamily::kRadTan && b.family == LensFamily::kRadTan) {
    cv::stereoRectify(m1, OpenCvDistortion(a), m2, OpenCvDistortion(b), size, r, t, *r1, *r2, *p1,
                      *p2, *q, cv::CALIB_ZERO_DISPARITY, -1);
    *method = "opencv";
    return true;
  }
  if (a.family == LensFamily::kEquidistant && b.family == LensFamily::kEquidistant) {
    cv::fisheye::stereoRectify(m1, OpenCvDistortion(a), m2, OpenCvDistortion(b), size, r, t, *r1,
                               *r2, *p1, *p2, *q, cv::CALIB_ZERO_DISPARITY);
    *method = "opencv-fisheye";
    return true;
  }
  const RectifySummary summary = RectifyPair(rig);
  if (!summary.ok) return Fail(why, summary.error);
  const Rectification& rect = summary.rectification;
  *r1 = ToMat(rect.rect_from_cam_a);
  *r2 = ToMat(rect.rect_from_cam_b);
  *p1 = ToMat(rect.P1());
  *p2 = ToMat(rect.P2());
  *q = ToMat(rect.Q());
  *method = "calibench";
  return true;
}

// A 3 x 3 R (proper rotation) and a 3-vector T from the file.
bool ReadPose(const std::string& path, const cv::FileStorage& in, Rigid3* pose, std::string* why) {
  cv::Mat r, t;
  in["R"] >> r;
  in["T"] >> t;
  if (r.empty()) return Fail(why, path + ": R: missing (the rotation, p_cam2 = R p_cam1 + T)");
  if (r.rows != 3 || r.cols != 3) {
    return Fail(why, path + ": R: expected a 3 x 3 matrix, got " + std::to_string(r.rows) + " x " +
                         std::to_string(r.cols));
  }
  if (t.empty()) return Fail(why, path + ": T: missing (the translation, p_cam2 = R p_cam1 + T)");
  if (t.total() != 3) {
    return Fail(why, path + ": T: expected 3 numbers, got " + std::to_string(t.total()));
  }
  r.convertTo(r, CV_64F);
  t.convertTo(t, CV_64F);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) pose->rotation(i, j) = r.at<double>(i, j);
    pose->translation(i) = t.at<double>(i);
  }
  if (!pose->translation.allFinite()) return Fail(why, path + ": T: non-finite entries");
  return CheckFileRotation(path + ": R", pose->rotation, why);
}

}  // namespace

bool WriteOpenCvRig(const std::string& path, const RigFile& rig, std::string* why) {
  if (rig.rig.NumCameras() != 2) {
    return Fail(why, path + ": opencv: a stereo file holds 2 cameras, the rig has " +
                         std::to_string(rig.rig.NumCameras()) + " (write kalibr or mrcal)");
  }
  const CameraRig& r = rig.rig;
  const Rigid3& pose = r.cameras[1].cam_from_rig;
  const Eigen::Matrix3d essential = Hat(pose.translation) * pose.rotation;
  Eigen::Matrix3d f = r.cameras[1].intrinsics.Matrix().inverse().transpose() * essential *
                      r.cameras[0].intrinsics.Matrix().inverse();
  if (std::abs(f(2, 2)) > 1e-300) f /= f(2, 2);  // As cv::stereoCalibrate scales it.
  cv::Mat r1, r2, p1, p2, q;
  std::string method = "none (image size unknown)";
  std::string rectify_why;
  if (r.cameras[0].image_width > 0 && !Rectify(r, &r1, &r2, &p1, &p2, &q, &method, &rectify_why)) {
    // The calibration is written all the same: a pair that cannot be rectified (cameras that look
    // apart) is still a rig.
    method = "none (" + rectify_why + ")";
    r1 = r2 = p1 = p2 = q = cv::Mat();
  }
  const std::string tmp = camera_io_internal::TemporaryBeside(path);
  try {
    cv::FileStorage out(tmp, cv::FileStorage::WRITE);
    if (!out.isOpened()) return Fail(why, path + ": cannot open for writing");
    for (int i = 1; i <= 2; ++i) {
      camera_io_internal::WriteOpenCvCamera(CameraFileOf(rig, i - 1), /*with_fit=*/false,
                                            StereoNames(i), &out);
    }
    out << "R" << ToMat(pose.rotation) << "T" << ToMat<3, 1>(pose.translation);
    out << "E" << ToMat(essential) << "F" << ToMat(f);
    out << "rectification" << method;
    if (!r1.empty()) {
      out << "R1" << r1 << "R2" << r2 << "P1" << p1 << "P2" << p2 << "Q" << q;
    }
    out.release();
  } catch (const cv::Exception& e) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return Fail(why, path + ": " + e.what());
  }
  return camera_io_internal::RenameInto(tmp, path, why);
}

bool ReadOpenCvRig(const std::string& path, RigFile* rig, std::string* why) {
  try {
    cv::FileStorage in(path, cv::FileStorage::READ);
    if (!in.isOpened()) return Fail(why, path + ": cannot open (not an OpenCV FileStorage file)");
    if (in["M1"].empty()) {
      return Fail(why, path + ": M1: missing (an OpenCV stereo file has M1 D1 M2 D2 R T)");
    }
    Rigid3 cam2_from_cam1;
    if (!ReadPose(path, in, &cam2_from_cam1, why)) return false;
    for (int i = 1; i <= 2; ++i) {
      CameraFile camera;
      if (!camera_io_internal::ReadOpenCvCamera(path, in, StereoNames(i), &camera, why)) {
        return false;
      }
      std::string reason;
      if (!camera.intrinsics.Check(&reason)) {
        return Fail(why, path + ": M" + std::to_string(i) + ": " + reason);
      }
      AddCamera(camera, i == 1 ? Rigid3() : cam2_from_cam1, rig);
    }
    return true;
  } catch (const cv::Exception& e) {
    return Fail(why, path + ": " + e.what());
  }
}

}  // namespace rig_io_internal
}  // namespace calibench
