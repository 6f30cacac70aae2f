// Stereo rectification of any lens family (calib/rectify.h): Bouguet's rotations against
// cv::stereoRectify, zero vertical disparity on exact projections of the true rig, the disparity a
// 0.2 deg error leaves, the focal-length rule and the side-by-side image.
#include "calib/rectify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace calibench {
namespace {

// R1 and R2 are the same formula as OpenCV's (Rodrigues of half the relative rotation, then the
// turn onto the baseline) in another order of operations: ~1e-16 apart; 1e-12 leaves room.
constexpr double kOpenCvRotationTol = 1e-12;
// Exact projections through the true rig: the rows differ only by the unprojection's iterations
// (1e-12 in normalised coordinates, camera.h) times f: ~1e-9 px; the bar of the task is 1e-6 px.
constexpr double kExactVerticalDisparityPx = 1e-6;

CameraIntrinsics RadTan(double f) {
  CameraIntrinsics k;
  k.fku_px = f, k.fkv_px = f * 1.002, k.u0_px = 322.5, k.v0_px = 238.25;
  k.k1 = -0.28, k.k2 = 0.09, k.p1 = 8e-4, k.p2 = -5e-4, k.k3 = -0.01;
  return k;
}

CameraIntrinsics DoubleSphere(double f) {
  CameraIntrinsics k;
  k.family = LensFamily::kDoubleSphere;
  k.fku_px = f, k.fkv_px = f * 0.9995, k.u0_px = 254.7, k.v0_px = 256.6;
  k.xi = -0.18, k.alpha = 0.59;
  return k;
}

CameraIntrinsics Equidistant(double f) {
  CameraIntrinsics k;
  k.family = LensFamily::kEquidistant;
  k.fku_px = f, k.fkv_px = f, k.u0_px = 255.0, k.v0_px = 257.0;
  k.k1 = 0.0035, k.k2 = 7e-4, k.k3 = -2e-3, k.k4 = 2e-4;
  return k;
}

// Camera 1 ~0.1 m to the right of camera 0, turned by ~2 deg.
CameraRig Rig(const CameraIntrinsics& a, const CameraIntrinsics& b, int width, int height) {
  CameraRig rig;
  for (const CameraIntrinsics* k : {&a, &b}) {
    RigCamera camera;
    camera.name = "cam" + std::to_string(rig.NumCameras());
    camera.intrinsics = *k;
    camera.lens_model = FullModelOf(k->family);
    camera.image_width = width, camera.image_height = height;
    rig.cameras.push_back(camera);
  }
  rig.cameras[1].cam_from_rig = {ExpSO3(Eigen::Vector3d(0.012, -0.031, 0.017)),
                                 Eigen::Vector3d(-0.1003, 0.0021, -0.0034)};
  return rig;
}

// Points in front of the rig (rig frame = board frame) at several depths, projected exactly by
// both cameras of `truth`; a point enters a view only where the camera sees it.
std::vector<RigFrame> ExactFrames(const CameraRig& truth, double half_angle_tan) {
  std::vector<RigFrame> frames;
  for (double depth : {0.8, 2.0, 6.0}) {
    RigFrame frame;
    frame.views_by_camera.resize(2);
    for (double x = -half_angle_tan; x <= half_angle_tan + 1e-9; x += half_angle_tan / 6) {
      for (double y = -half_angle_tan; y <= half_angle_tan + 1e-9; y += half_angle_tan / 6) {
        const Eigen::Vector3d p(x * depth, y * depth, depth);
        for (int c = 0; c < 2; ++c) {
          const RigCamera& camera = truth.cameras[c];
          Eigen::Vector2d q;
          if (!ProjectPoint(camera.intrinsics, camera.cam_from_rig * p, &q) || q.x() < 0 ||
              q.y() < 0 || q.x() > camera.image_width - 1 || q.y() > camera.image_height - 1) {
            continue;
          }
          frame.views_by_camera[c].points.push_back(p);
          frame.views_by_camera[c].pixels.push_back(q);
        }
      }
    }
    frames.push_back(frame);
  }
  return frames;
}

Eigen::Matrix3d FromMat(const cv::Mat& m) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = m.at<double>(r, c);
  }
  return out;
}

TEST(Rectify, RotationsAreOpenCvsForRadTan) {
  const CameraRig rig = Rig(RadTan(800), RadTan(790), 640, 480);
  const RectifySummary summary = RectifyPair(rig);
  ASSERT_TRUE(summary.ok) << summary.error;
  const auto mat = [](const Eigen::Matrix3d& m) {
    cv::Mat out(3, 3, CV_64F);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) out.at<double>(r, c) = m(r, c);
    }
    return out;
  };
  const auto dist = [](const CameraIntrinsics& k) {
    return cv::Mat((cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3));
  };
  const Rigid3& pose = rig.cameras[1].cam_from_rig;
  const cv::Mat t =
      (cv::Mat_<double>(3, 1) << pose.translation.x(), pose.translation.y(), pose.translation.z());
  cv::Mat r1, r2, p1, p2, q;
  cv::stereoRectify(mat(rig.cameras[0].intrinsics.Matrix()), dist(rig.cameras[0].intrinsics),
                    mat(rig.cameras[1].intrinsics.Matrix()), dist(rig.cameras[1].intrinsics),
                    cv::Size(640, 480), mat(pose.rotation), t, r1, r2, p1, p2, q,
                    cv::CALIB_ZERO_DISPARITY, -1);
  const Rectification& r = summary.rectification;
  EXPECT_LT((FromMat(r1) - r.rect_from_cam_a).cwiseAbs().maxCoeff(), kOpenCvRotationTol);
  EXPECT_LT((FromMat(r2) - r.rect_from_cam_b).cwiseAbs().maxCoeff(), kOpenCvRotationTol);
  // P2's baseline term is f times the rectified x of camera 0's centre seen from camera 1.
  EXPECT_NEAR(p2.at<double>(0, 3) / p2.at<double>(0, 0), r.baseline_x, 1e-12);
  EXPECT_NEAR(r.baseline_x, -rig.BaselineM(1), 1e-12);  // Along x only, camera 1 on the right.
  EXPECT_DOUBLE_EQ(r.P2()(0, 3), r.f_px * r.baseline_x);
  EXPECT_DOUBLE_EQ(r.Q()(3, 2), -1.0 / r.baseline_x);
}

TEST(Rectify, ExactProjectionsHaveNoVerticalDisparity) {
  struct Case {
    const char* name;
    CameraRig rig;
    double half_angle_tan;
  };
  const std::vector<Case> cases = {
      {"radtan", Rig(RadTan(800), RadTan(790), 640, 480), 0.35},
      {"double-sphere", Rig(DoubleSphere(158), DoubleSphere(160), 512, 512), 2.0},
      {"equidistant + double-sphere", Rig(Equidistant(190), DoubleSphere(158), 512, 512), 2.0},
  };
  for (const Case& c : cases) {
    const RectifySummary summary = RectifyPair(c.rig);
    ASSERT_TRUE(summary.ok) << c.name << ": " << summary.error;
    const VerticalDisparity d = MeasureVerticalDisparity(c.rig, summary.rectification,
                                                         ExactFrames(c.rig, c.half_angle_tan));
    EXPECT_GT(d.points, 150) << c.name;
    EXPECT_LT(d.max_px, kExactVerticalDisparityPx) << c.name;
    EXPECT_LE(d.rms_px, d.max_px) << c.name;
  }
}

// Camera 1 turned 0.2 deg about its x axis (a pitch) in the rig that is rectified but not in the
// one that projects: rows differ by about f * tan(0.2 deg) = f * 0.0035 px.
TEST(Rectify, AWrongRotationShowsAsVerticalDisparity) {
  const double error_rad = 0.2 * M_PI / 180;
  for (bool omni : {false, true}) {
    const CameraRig truth = omni ? Rig(DoubleSphere(158), DoubleSphere(160), 512, 512)
                                 : Rig(RadTan(800), RadTan(790), 640, 480);
    CameraRig wrong = truth;
    Rigid3& pose = wrong.cameras[1].cam_from_rig;
    pose.rotation = ExpSO3(Eigen::Vector3d(error_rad, 0, 0)) * pose.rotation;
    const RectifySummary summary = RectifyPair(wrong);
    ASSERT_TRUE(summary.ok) << summary.error;
    const double f = summary.rectification.f_px;
    const VerticalDisparity d = MeasureVerticalDisparity(wrong, summary.rectification,
                                                         ExactFrames(truth, omni ? 0.8 : 0.3));
    const double expected = f * std::tan(error_rad);
    // The shift of a row y (normalised) under a turn about x is f (1 + y^2) delta: the RMS over
    // the points is a little above f delta (their |y| <= 0.8 on the rectified image's centre).
    EXPECT_GT(d.rms_px, 0.95 * expected) << (omni ? "omni " : "radtan ") << d.rms_px;
    EXPECT_LT(d.rms_px, 1.35 * expected) << (omni ? "omni " : "radtan ") << d.rms_px;
    EXPECT_GE(d.max_px, d.rms_px);
    std::printf(
        "%s: f %.3f px, vertical disparity rms %.4f px, max %.4f px, f tan(0.2 deg) "
        "%.4f px\n",
        omni ? "double-sphere" : "radtan", f, d.rms_px, d.max_px, expected);
  }
}

// The focal-length rule: every border pixel of the rectified images has a source pixel in both
// images; a 2 % wider view (smaller f) does not.
TEST(Rectify, FocalLengthKeepsOnlyValidPixels) {
  for (const CameraRig& rig : {Rig(RadTan(800), RadTan(790), 640, 480),
                               Rig(Equidistant(190), DoubleSphere(158), 512, 512)}) {
    const RectifySummary summary = RectifyPair(rig);
    ASSERT_TRUE(summary.ok) << summary.error;
    for (double scale : {1.0, 0.98}) {
      Rectification r = summary.rectification;
      r.f_px *= scale;
      int outside = 0;
      for (int which = 0; which < 2; ++which) {
        const RigCamera& camera = rig.cameras[which];
        const RectifyMap map = RectifyMaps(rig, r, which);
        ASSERT_EQ(map.x.size(), static_cast<size_t>(r.width) * r.height);
        for (size_t i = 0; i < map.x.size(); ++i) {
          const bool inside = map.x[i] >= -0.5f && map.y[i] >= -0.5f &&
                              map.x[i] <= camera.image_width - 0.5f &&
                              map.y[i] <= camera.image_height - 0.5f;
          outside += inside ? 0 : 1;
        }
      }
      if (scale == 1.0) {
        EXPECT_EQ(outside, 0) << ToString(rig.cameras[1].intrinsics.family);
      } else {
        EXPECT_GT(outside, 0) << ToString(rig.cameras[1].intrinsics.family);
      }
    }
  }
}

// The remap table sends the rectified pixel of a point to the pixel the camera sees it at.
TEST(Rectify, MapsFollowTheLens) {
  const CameraRig rig = Rig(Equidistant(190), DoubleSphere(158), 512, 512);
  const RectifySummary summary = RectifyPair(rig);
  ASSERT_TRUE(summary.ok) << summary.error;
  const Rectification& r = summary.rectification;
  for (int which = 0; which < 2; ++which) {
    const RectifyMap map = RectifyMaps(rig, r, which);
    const Eigen::Matrix3d& rect_from_cam = which == 0 ? r.rect_from_cam_a : r.rect_from_cam_b;
    for (const Eigen::Vector2i& uv :
         {Eigen::Vector2i(10, 20), Eigen::Vector2i(256, 256), Eigen::Vector2i(500, 400)}) {
      const Eigen::Vector3d ray_rect((uv.x() - r.cx_px) / r.f_px, (uv.y() - r.cy_px) / r.f_px, 1);
      Eigen::Vector2d q;
      ASSERT_TRUE(ProjectPoint(rig.cameras[which].intrinsics,
                               rect_from_cam.transpose() * (3.0 * ray_rect), &q));
      const size_t i = static_cast<size_t>(uv.y()) * r.width + uv.x();
      EXPECT_NEAR(map.x[i], q.x(), 1e-4);  // Stored as float: ~3e-5 px at 500 px.
      EXPECT_NEAR(map.y[i], q.y(), 1e-4);
    }
  }
}

TEST(Rectify, SideBySideImageHasBothHalvesAndLines) {
  const CameraRig rig = Rig(RadTan(800), RadTan(790), 640, 480);
  const RectifySummary summary = RectifyPair(rig);
  ASSERT_TRUE(summary.ok) << summary.error;
  GrayImage a, b;
  a.width = b.width = 640, a.height = b.height = 480;
  a.pixels.assign(640 * 480, 100);
  b.pixels.assign(640 * 480, 200);
  const GrayImage pair = RectifiedPairImage(rig, summary.rectification, a, b, 40);
  ASSERT_EQ(pair.width, 1280);
  ASSERT_EQ(pair.height, 480);
  EXPECT_EQ(pair.at(320, 5), 100);  // Row 5 carries no line (lines at 20, 60, ..).
  EXPECT_EQ(pair.at(960, 5), 200);
  EXPECT_EQ(pair.at(0, 20), 255);  // A dashed line: white then black every 8 px.
  EXPECT_EQ(pair.at(8, 20), 0);
  EXPECT_EQ(pair.at(0, 21), 100);
}

TEST(Rectify, RefusesWhatItCannotRectify) {
  CameraRig rig = Rig(RadTan(800), RadTan(790), 640, 480);
  rig.cameras[0].image_width = rig.cameras[0].image_height = 0;
  RectifySummary summary = RectifyPair(rig);
  EXPECT_FALSE(summary.ok);
  EXPECT_NE(summary.error.find("cam0: image size unknown"), std::string::npos) << summary.error;
  rig = Rig(RadTan(800), RadTan(790), 640, 480);
  RectifyOptions options;
  options.camera_b = 0;
  summary = RectifyPair(rig, options);
  EXPECT_FALSE(summary.ok);
  EXPECT_NE(summary.error.find("two different camera indices"), std::string::npos);
  options.camera_b = 2;
  summary = RectifyPair(rig, options);
  EXPECT_NE(summary.error.find("the rig has 2 cameras"), std::string::npos) << summary.error;
}

}  // namespace
}  // namespace calibench
