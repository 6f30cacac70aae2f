// Rig files (io/rig_io.h): round trips of 2- and 3-camera rigs through kalibr, opencv and mrcal,
// the epipolar geometry of the OpenCV stereo file, Kalibr's T_cn_cnm1 direction on a hand-made
// camchain, and bad files refused with the file, the field and the reason.
#include "io/rig_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>

namespace calibench {
namespace {

// A 2-camera pose goes through the files unchanged (17 digits; a product with the identity is
// exact); a chained pose (3 cameras) or a Rodrigues vector (mrcal) adds a few roundings of unit
// rotations and metre translations: 1e-14 is ~50 ulps.
constexpr double kChainedPoseTol = 1e-14;

std::string Temp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

CameraIntrinsics RadTan4(double f, double k1) {
  CameraIntrinsics k;
  k.fku_px = f, k.fkv_px = f * 1.0012345678901234;
  k.u0_px = 321.123456789, k.v0_px = 239.87654321;
  k.k1 = k1, k.k2 = 0.0712345, k.p1 = 1.2e-3, k.p2 = -2.3e-4;
  return k;
}

CameraIntrinsics Equidistant() {
  CameraIntrinsics k;
  k.family = LensFamily::kEquidistant;
  k.fku_px = 190.97847715128717, k.fkv_px = 190.9733070521226;
  k.u0_px = 254.93170605935475, k.v0_px = 256.8974428996504;
  k.k1 = 0.0034823894022493434, k.k2 = 0.0007150348452162257;
  k.k3 = -0.0020532361418706202, k.k4 = 0.00020293673591811182;
  return k;
}

CameraIntrinsics DoubleSphere() {
  CameraIntrinsics k;
  k.family = LensFamily::kDoubleSphere;
  k.fku_px = 158.2767, k.fkv_px = 158.2540, k.u0_px = 254.7285, k.v0_px = 256.5690;
  k.xi = -0.1797, k.alpha = 0.5915;
  return k;
}

RigCamera Camera(const CameraIntrinsics& k, int width, int height, const Eigen::Vector3d& r,
                 const Eigen::Vector3d& t) {
  RigCamera camera;
  camera.intrinsics = k;
  camera.lens_model = FullModelOf(k.family);
  if (k.family == LensFamily::kRadTan) {
    camera.lens_model = k.k3 != 0 ? LensModel::kPinholeRadTan5 : LensModel::kPinholeRadTan4;
  }
  camera.image_width = width, camera.image_height = height;
  camera.cam_from_rig = {ExpSO3(r), t};
  return camera;
}

// A horizontal stereo pair (camera 1 0.12 m to the right, turned by ~1 deg) and a third camera
// above, both pinhole + radtan4.
RigFile RadTanRig(int cameras) {
  RigFile file;
  file.rig.cameras.push_back(
      Camera(RadTan4(812.123456789012, -0.2513), 640, 480, Eigen::Vector3d::Zero(), {0, 0, 0}));
  file.rig.cameras.push_back(Camera(RadTan4(805.98765432109, -0.2417), 640, 480,
                                    {0.0123, -0.0171, 0.0042}, {-0.1200123456789, 0.0011, 0.0023}));
  if (cameras == 3) {
    file.rig.cameras.push_back(
        Camera(RadTan4(790.5, -0.2), 752, 480, {-0.03, 0.2, -0.01}, {0.003, 0.0812345, -0.0151}));
  }
  for (RigCamera& c : file.rig.cameras) c.name = "cam" + std::to_string(&c - &file.rig.cameras[0]);
  return file;
}

// A TUM VI-like fisheye pair of two lens families plus a radtan camera.
RigFile MixedRig(int cameras) {
  RigFile file;
  file.rig.cameras.push_back(Camera(Equidistant(), 512, 512, Eigen::Vector3d::Zero(), {0, 0, 0}));
  file.rig.cameras.push_back(
      Camera(DoubleSphere(), 512, 512, {-0.0472, 0.0011, -0.0013}, {-0.10103, 0.0019, 0.0007}));
  if (cameras == 3) {
    file.rig.cameras.push_back(
        Camera(RadTan4(600, -0.1), 640, 400, {0.01, -0.5, 0.02}, {0.2, -0.01, 0.05}));
  }
  return file;
}

void ExpectSameRig(const RigFile& written, const RigFile& read, double pose_tol,
                   bool lens_model_kept, const std::string& what) {
  ASSERT_EQ(read.rig.NumCameras(), written.rig.NumCameras()) << what;
  for (int c = 0; c < written.rig.NumCameras(); ++c) {
    const RigCamera& a = written.rig.cameras[c];
    const RigCamera& b = read.rig.cameras[c];
    EXPECT_EQ(b.name, "cam" + std::to_string(c)) << what;
    EXPECT_TRUE(a.intrinsics == b.intrinsics) << what << " camera " << c;
    EXPECT_EQ(a.image_width, b.image_width) << what;
    EXPECT_EQ(a.image_height, b.image_height) << what;
    if (lens_model_kept) {
      EXPECT_EQ(a.lens_model, b.lens_model) << what << " camera " << c;
    }
    const double rotation_error =
        (a.cam_from_rig.rotation - b.cam_from_rig.rotation).cwiseAbs().maxCoeff();
    const double translation_error =
        (a.cam_from_rig.translation - b.cam_from_rig.translation).cwiseAbs().maxCoeff();
    if (pose_tol == 0) {
      EXPECT_TRUE(a.cam_from_rig == b.cam_from_rig)
          << what << " camera " << c << ": " << rotation_error << " " << translation_error;
    } else {
      EXPECT_LE(rotation_error, pose_tol) << what << " camera " << c;
      EXPECT_LE(translation_error, pose_tol) << what << " camera " << c;
    }
  }
}

TEST(RigFile, KalibrRoundTrips) {
  for (int n : {2, 3}) {
    for (bool mixed : {false, true}) {
      RigFile rig = mixed ? MixedRig(n) : RadTanRig(n);
      rig.cam_overlaps.resize(n);
      for (int c = 0; c < n; ++c) {
        for (int o = 0; o < n; ++o) {
          if (o != c) rig.cam_overlaps[c].push_back(o);
        }
        rig.rostopics.push_back("/cam" + std::to_string(c) + "/image_raw");
      }
      const std::string path = Temp("rig-camchain.yaml");
      ASSERT_EQ(CameraFormatFromPath(path), CameraFormat::kKalibr);
      std::string why;
      ASSERT_TRUE(WriteRigFile(path, CameraFormat::kKalibr, rig, &why)) << why;
      RigFile back;
      ASSERT_TRUE(ReadRigFile(path, &back, &why)) << why;
      const std::string what = "kalibr " + std::to_string(n) + (mixed ? " mixed" : " radtan");
      ExpectSameRig(rig, back, n == 2 ? 0.0 : kChainedPoseTol, /*lens_model_kept=*/true, what);
      EXPECT_EQ(back.cam_overlaps, rig.cam_overlaps) << what;
      EXPECT_EQ(back.rostopics, rig.rostopics) << what;
      EXPECT_TRUE(back.intrinsics_std.empty()) << what;
    }
  }
}

TEST(RigFile, OpenCvStereoRoundTrips) {
  for (int pair = 0; pair < 3; ++pair) {
    RigFile rig = pair == 0 ? RadTanRig(2) : MixedRig(2);
    if (pair == 0) {
      rig.rig.cameras[0].intrinsics.k3 = 0.0131;  // OpenCV holds k3 and skew.
      rig.rig.cameras[0].intrinsics.phi_deg = 90.01234567890123;
      rig.rig.cameras[0].lens_model = LensModel::kPinholeRadTan5;
      rig.intrinsics_std.resize(2);
      for (IntrinsicsArray& s : rig.intrinsics_std) s.fill(std::nan(""));
      rig.intrinsics_std[1][0] = 0.25, rig.intrinsics_std[1][5] = 1.5e-3;
    }
    if (pair == 2) {  // Both equidistant: cv::fisheye::stereoRectify.
      rig.rig.cameras[1].intrinsics = Equidistant();
      rig.rig.cameras[1].intrinsics.fku_px += 1.0;
      rig.rig.cameras[1].lens_model = LensModel::kPinholeEqui;
    }
    for (const char* ext : {".yaml", ".xml", ".json"}) {
      const std::string path = Temp(std::string("stereo") + ext);
      ASSERT_EQ(CameraFormatFromPath(path), CameraFormat::kOpenCv);
      std::string why;
      ASSERT_TRUE(WriteRigFile(path, CameraFormat::kOpenCv, rig, &why)) << why;
      RigFile back;
      ASSERT_TRUE(ReadRigFile(path, &back, &why)) << why;
      const std::string what = std::string("opencv ") + ext + " pair " + std::to_string(pair);
      ExpectSameRig(rig, back, 0.0, /*lens_model_kept=*/true, what);
      if (pair == 0) {
        ASSERT_EQ(back.intrinsics_std.size(), 2u) << what;
        EXPECT_EQ(back.intrinsics_std[1][0], 0.25) << what;
        EXPECT_EQ(back.intrinsics_std[1][5], 1.5e-3) << what;
        EXPECT_TRUE(std::isnan(back.intrinsics_std[0][0])) << what;
      } else {
        EXPECT_TRUE(back.intrinsics_std.empty()) << what;
      }
      cv::FileStorage in(path, cv::FileStorage::READ);
      std::string method;
      in["rectification"] >> method;
      EXPECT_EQ(method, pair == 0 ? "opencv" : pair == 1 ? "calibench" : "opencv-fisheye");
      for (const char* field :
           {"M1", "D1", "M2", "R", "T", "E", "F", "R1", "R2", "P1", "P2", "Q"}) {
        EXPECT_FALSE(in[field].empty()) << what << ": " << field;
      }
      // The double sphere has no distortion coefficients: xi_2 and alpha_2 instead of D2.
      EXPECT_EQ(in["D2"].empty(), pair == 1) << what;
      EXPECT_EQ(in["xi_2"].empty(), pair != 1) << what;
    }
  }
  std::string why;
  EXPECT_FALSE(WriteRigFile(Temp("three.yaml"), CameraFormat::kOpenCv, RadTanRig(3), &why));
  EXPECT_NE(why.find("a stereo file holds 2 cameras, the rig has 3"), std::string::npos) << why;
}

// E = [T]x R and F = M2^-T E M1^-1 of the stereo file: x2^T F x1 = 0 for the pinhole pixels of
// the undistorted rays of points seen by both cameras.
TEST(RigFile, OpenCvEssentialAndFundamentalMatchThePose) {
  // E and F are products of a few 17-digit numbers: the epipolar distance of exact points is at
  // rounding level, ~1e-12 px at 800 px; 1e-9 px is a clear bar that a wrong sign or transpose
  // (pixels off by the disparity) fails by orders of magnitude.
  constexpr double kEpipolarDistancePx = 1e-9;
  const RigFile rig = RadTanRig(2);
  const std::string path = Temp("stereo_ef.yaml");
  std::string why;
  ASSERT_TRUE(WriteRigFile(path, CameraFormat::kOpenCv, rig, &why)) << why;
  cv::FileStorage in(path, cv::FileStorage::READ);
  cv::Mat e_mat, f_mat;
  in["E"] >> e_mat;
  in["F"] >> f_mat;
  ASSERT_EQ(e_mat.rows, 3);
  ASSERT_EQ(f_mat.rows, 3);
  Eigen::Matrix3d e, f;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) e(r, c) = e_mat.at<double>(r, c), f(r, c) = f_mat.at<double>(r, c);
  }
  const Rigid3& cam1_from_cam0 = rig.rig.cameras[1].cam_from_rig;
  const Eigen::Matrix3d m0 = rig.rig.cameras[0].intrinsics.Matrix();
  const Eigen::Matrix3d m1 = rig.rig.cameras[1].intrinsics.Matrix();
  int checked = 0;
  double worst_wrong_pose = 0;
  for (double x = -1.0; x <= 1.0; x += 0.25) {
    for (double y = -0.6; y <= 0.6; y += 0.3) {
      for (double z : {0.7, 2.0, 9.0}) {
        const Eigen::Vector3d p0(x * z * 0.5, y * z * 0.5, z);
        const Eigen::Vector3d p1 = cam1_from_cam0 * p0;
        const Eigen::Vector3d x0 = m0 * (p0 / p0.z()), x1 = m1 * (p1 / p1.z());
        EXPECT_NEAR((p1 / p1.norm()).dot(e * (p0 / p0.norm())), 0, 1e-15);
        const Eigen::Vector3d line = f * x0;
        const double distance = x1.dot(line) / line.head<2>().norm();
        EXPECT_LT(std::abs(distance), kEpipolarDistancePx) << x << " " << y << " " << z;
        const Eigen::Vector3d wrong = f.transpose() * x0;  // F^T: the other direction.
        worst_wrong_pose =
            std::max(worst_wrong_pose, std::abs(x1.dot(wrong)) / wrong.head<2>().norm());
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
  EXPECT_GT(worst_wrong_pose, 1.0);  // The test can tell F from F^T.
}

TEST(RigFile, MrcalRoundTripsEveryCameraFile) {
  for (int n : {2, 3}) {
    RigFile rig = RadTanRig(n);
    rig.rig.cameras[1].intrinsics.k3 = 0.0131;  // LENSMODEL_OPENCV5.
    rig.rig.cameras[1].lens_model = LensModel::kPinholeRadTan5;
    const std::string path = Temp("rig.cameramodel");
    std::string why;
    ASSERT_TRUE(WriteRigFile(path, CameraFormat::kMrcal, rig, &why)) << why;
    const std::vector<std::string> paths = MrcalRigPaths(path, n);
    EXPECT_EQ(std::filesystem::path(paths[1]).lexically_normal(),
              std::filesystem::path(Temp("rig-camera-1.cameramodel")).lexically_normal());
    for (const std::string& p : paths) EXPECT_TRUE(std::filesystem::exists(p)) << p;
    RigFile back;
    ASSERT_TRUE(ReadRigFile(path, &back, &why)) << why;
    ExpectSameRig(rig, back, kChainedPoseTol, /*lens_model_kept=*/true,
                  "mrcal " + std::to_string(n));
    RigFile from_one_file;  // Named by one of its files, the set reads the same.
    ASSERT_TRUE(ReadRigFile(paths[1], &from_one_file, &why)) << why;
    EXPECT_EQ(from_one_file.rig.NumCameras(), n);
    std::filesystem::remove(paths.back());  // Next loop: a 2-camera set reads as 2 cameras.
  }
  std::string why;
  EXPECT_FALSE(WriteRigFile(Temp("fish.cameramodel"), CameraFormat::kMrcal, MixedRig(2), &why));
  EXPECT_NE(why.find("mrcal 2.2 has no"), std::string::npos) << why;
  EXPECT_NE(why.find("fish-camera-0.cameramodel"), std::string::npos) << why;
}

// mrcal files whose reference is not camera 0: the rig is re-expressed in camera 0's frame.
TEST(RigFile, MrcalReferenceOtherThanCameraZero) {
  const RigFile rig = RadTanRig(3);
  const Rigid3 cam0_from_ref = {ExpSO3(Eigen::Vector3d(0.3, -0.2, 0.1)), {1.0, 2.0, -0.5}};
  const std::vector<std::string> paths = MrcalRigPaths(Temp("ref.cameramodel"), 3);
  for (int c = 0; c < 3; ++c) {
    // Each camera written with its extrinsics cam_from_ref.
    const Rigid3 cam_from_ref = rig.rig.cameras[c].cam_from_rig * cam0_from_ref;
    const Eigen::Vector3d r = LogSO3(cam_from_ref.rotation);
    std::ofstream out(paths[c]);
    out.precision(17);
    const CameraIntrinsics& k = rig.rig.cameras[c].intrinsics;
    out << "{ 'lensmodel': 'LENSMODEL_OPENCV4', 'intrinsics': [" << k.fku_px << ", " << k.fkv_px
        << ", " << k.u0_px << ", " << k.v0_px << ", " << k.k1 << ", " << k.k2 << ", " << k.p1
        << ", " << k.p2 << "], 'extrinsics': [" << r.x() << ", " << r.y() << ", " << r.z() << ", "
        << cam_from_ref.translation.x() << ", " << cam_from_ref.translation.y() << ", "
        << cam_from_ref.translation.z() << "], 'imagersize': [" << rig.rig.cameras[c].image_width
        << ", " << rig.rig.cameras[c].image_height << "] }\n";
  }
  RigFile back;
  std::string why;
  ASSERT_TRUE(ReadRigFile(Temp("ref.cameramodel"), &back, &why)) << why;
  // Three products of Rodrigues rotations with translations of ~2 m.
  ExpectSameRig(rig, back, 1e-13, /*lens_model_kept=*/false, "mrcal, reference elsewhere");
}

// Kalibr's T_cn_cnm1 maps camera n-1's points into camera n: a hand-made camchain with cam1 0.1 m
// to the right of cam0 (cam0's centre at x = -0.1 in cam1) and cam2 turned 90 deg about cam1's
// optical axis and 0.2 m further along its x.
TEST(RigFile, KalibrTransformDirection) {
  const std::string camera =
      "  camera_model: pinhole\n  intrinsics: [500, 500, 320, 240]\n"
      "  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n";
  const std::string path = Temp("hand-camchain.yaml");
  std::ofstream(path) << "cam0:\n"
                      << camera << "  cam_overlaps: [1]\n"
                      << "cam1:\n  T_cn_cnm1:\n  - [1, 0, 0, -0.1]\n  - [0, 1, 0, 0]\n"
                      << "  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n"
                      << camera << "cam2:\n  T_cn_cnm1:\n  - [0, -1, 0, -0.2]\n  - [1, 0, 0, 0]\n"
                      << "  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n"
                      << camera;
  RigFile rig;
  std::string why;
  ASSERT_TRUE(ReadRigFile(path, &rig, &why)) << why;
  ASSERT_EQ(rig.rig.NumCameras(), 3);
  EXPECT_EQ(rig.rig.cameras[1].cam_from_rig.translation, Eigen::Vector3d(-0.1, 0, 0));
  EXPECT_EQ(rig.rig.CentreInRig(1), Eigen::Vector3d(0.1, 0, 0));  // To the right of cam0.
  // A point 1 m in front of cam0: in cam1 at x = -0.1; in cam2, cam1's (x, y) = (-0.1, 0) turned
  // by 90 deg about z is (0, -0.1), then 0.2 m along -x.
  const Eigen::Vector3d p(0, 0, 1);
  EXPECT_TRUE((rig.rig.cameras[1].cam_from_rig * p).isApprox(Eigen::Vector3d(-0.1, 0, 1)));
  EXPECT_TRUE((rig.rig.cameras[2].cam_from_rig * p).isApprox(Eigen::Vector3d(-0.2, -0.1, 1)));
  EXPECT_EQ(rig.cam_overlaps[0], std::vector<int>{1});
  EXPECT_TRUE(rig.cam_overlaps[1].empty());
  // Written back, cam1's T_cn_cnm1 is the same matrix.
  ASSERT_TRUE(WriteRigFile(path, CameraFormat::kKalibr, rig, &why)) << why;
  RigFile again;
  ASSERT_TRUE(ReadRigFile(path, &again, &why)) << why;
  EXPECT_TRUE(again.rig.CamFromCam(1, 0) == rig.rig.CamFromCam(1, 0));
}

// A file as OpenCV's stereo_calib.cpp sample writes it (M1 D1 M2 D2 from intrinsics.yml, R T from
// extrinsics.yml, in one file; none of calibench's fields): radtan cameras, p_cam2 = R p_cam1 + T.
TEST(RigFile, OpenCvSampleStyleFileReads) {
  const std::string path = Temp("sample_stereo.yml");
  {
    cv::FileStorage out(path, cv::FileStorage::WRITE);
    out << "M1" << (cv::Mat_<double>(3, 3) << 530.5, 0, 338.2, 0, 530.1, 233.4, 0, 0, 1);
    out << "D1" << (cv::Mat_<double>(1, 5) << -0.27, 0.02, 0.001, -0.0003, 0.1);
    out << "M2" << (cv::Mat_<double>(3, 3) << 529.2, 0, 325.7, 0, 529.0, 248.1, 0, 0, 1);
    out << "D2" << (cv::Mat_<double>(1, 8) << -0.29, 0.11, -0.0006, 0.0002, -0.03, 0, 0, 0);
    out << "R" << cv::Mat::eye(3, 3, CV_64F);
    out << "T" << (cv::Mat_<double>(3, 1) << -3.33, 0.04, -0.01);  // In squares, as the sample.
  }
  RigFile rig;
  std::string why;
  ASSERT_TRUE(ReadRigFile(path, &rig, &why)) << why;
  ASSERT_EQ(rig.rig.NumCameras(), 2);
  EXPECT_EQ(rig.rig.cameras[0].intrinsics.fku_px, 530.5);
  EXPECT_EQ(rig.rig.cameras[0].intrinsics.k3, 0.1);
  EXPECT_EQ(rig.rig.cameras[0].lens_model, LensModel::kPinholeRadTan5);
  EXPECT_EQ(rig.rig.cameras[1].intrinsics.v0_px, 248.1);
  EXPECT_EQ(rig.rig.cameras[1].cam_from_rig.translation, Eigen::Vector3d(-3.33, 0.04, -0.01));
  EXPECT_GT(rig.rig.CentreInRig(1).x(), 3.3);    // The right camera, seen from the left one.
  EXPECT_EQ(rig.rig.cameras[1].image_width, 0);  // The sample writes no image size.
}

TEST(RigFile, BadFilesNameFileFieldAndReason) {
  const std::string camera =
      "  camera_model: pinhole\n  intrinsics: [500, 500, 320, 240]\n"
      "  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n";
  struct Case {
    std::string name, text, reason;
  };
  const std::vector<Case> cases = {
      {"missing-camchain.yaml", "cam0:\n" + camera + "cam1:\n" + camera, "cam1.T_cn_cnm1: missing"},
      {"three-rows-camchain.yaml",
       "cam0:\n" + camera + "cam1:\n  T_cn_cnm1: [[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0]]\n" +
           camera,
       "cam1.T_cn_cnm1: expected a 4 x 4 matrix"},
      {"three-cols-camchain.yaml",
       "cam0:\n" + camera + "cam1:\n  T_cn_cnm1: [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 0]]\n" +
           camera,
       "cam1.T_cn_cnm1: expected a 4 x 4 matrix"},
      {"improper-camchain.yaml",
       "cam0:\n" + camera +
           "cam1:\n  T_cn_cnm1: [[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1]]\n" +
           camera,
       "cam1.T_cn_cnm1: improper rotation"},
      {"skewed-camchain.yaml",
       "cam0:\n" + camera +
           "cam1:\n  T_cn_cnm1: [[1, 0.1, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n" +
           camera,
       "cam1.T_cn_cnm1: rotation is not orthonormal"},
      {"one-camchain.yaml", "cam0:\n" + camera, "a rig needs cam0 and cam1"},
      {"same-centre-camchain.yaml",
       "cam0:\n" + camera +
           "cam1:\n  T_cn_cnm1: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n" +
           camera,
       "cam1: cam_from_rig: its centre coincides with camera 0's"},
      {"bad-intrinsics-camchain.yaml",
       "cam0:\n" + camera + "cam1:\n  T_cn_cnm1: [[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0], " +
           "[0, 0, 0, 1]]\n  camera_model: pinhole\n  intrinsics: [500, 500, 320]\n" +
           "  resolution: [640, 480]\n",
       "cam1.intrinsics: expected a list of 4 numbers"},
  };
  for (const Case& c : cases) {
    const std::string path = Temp(c.name);
    std::ofstream(path) << c.text;
    RigFile rig;
    std::string why;
    EXPECT_FALSE(ReadRigFile(path, &rig, &why)) << c.name;
    EXPECT_EQ(why.rfind(path, 0), 0u) << why;
    EXPECT_NE(why.find(c.reason), std::string::npos) << c.name << ": " << why;
  }
  // OpenCV stereo files: R, T of the wrong size, an improper R, a missing M2.
  const RigFile good = RadTanRig(2);
  struct OpenCvCase {
    std::string name;
    cv::Mat r, t;
    std::string reason;
  };
  const std::vector<OpenCvCase> opencv_cases = {
      {"r2x2.yaml", cv::Mat::eye(2, 2, CV_64F), (cv::Mat_<double>(3, 1) << -0.1, 0, 0),
       ": R: expected a 3 x 3 matrix, got 2 x 2"},
      {"t4.yaml", cv::Mat::eye(3, 3, CV_64F), (cv::Mat_<double>(4, 1) << -0.1, 0, 0, 1),
       ": T: expected 3 numbers, got 4"},
      {"improper.yaml", cv::Mat::diag(cv::Mat(cv::Vec3d(1, -1, 1))),
       (cv::Mat_<double>(3, 1) << -0.1, 0, 0), ": R: improper rotation"},
      {"no-m2.yaml", cv::Mat::eye(3, 3, CV_64F), (cv::Mat_<double>(3, 1) << -0.1, 0, 0),
       ": M2: expected a 3 x 3 matrix"},
  };
  for (const OpenCvCase& c : opencv_cases) {
    const std::string path = Temp(c.name);
    {
      cv::FileStorage out(path, cv::FileStorage::WRITE);
      out << "M1" << (cv::Mat_<double>(3, 3) << 500, 0, 320, 0, 500, 240, 0, 0, 1);
      out << "D1" << cv::Mat::zeros(1, 5, CV_64F);
      if (c.name != "no-m2.yaml") out << "M2" << cv::Mat::eye(3, 3, CV_64F);
      out << "D2" << cv::Mat::zeros(1, 5, CV_64F) << "R" << c.r << "T" << c.t;
    }
    RigFile rig;
    std::string why;
    EXPECT_FALSE(ReadRigFile(path, &rig, &why)) << c.name;
    EXPECT_EQ(why.rfind(path, 0), 0u) << why;
    EXPECT_NE(why.find(c.reason), std::string::npos) << c.name << ": " << why;
  }
  // An mrcal set with a camera missing its extrinsics.
  std::string why;
  ASSERT_TRUE(WriteRigFile(Temp("noext.cameramodel"), CameraFormat::kMrcal, good, &why)) << why;
  const std::string one = MrcalRigPaths(Temp("noext.cameramodel"), 2)[1];
  std::ofstream(one) << "{ 'lensmodel': 'LENSMODEL_PINHOLE', 'intrinsics': [500, 500, 320, 240], "
                        "'imagersize': [640, 480] }\n";
  RigFile rig;
  EXPECT_FALSE(ReadRigFile(Temp("noext.cameramodel"), &rig, &why));
  EXPECT_NE(why.find(one + ": extrinsics: missing"), std::string::npos) << why;
  EXPECT_FALSE(ReadRigFile(Temp("nothing.cameramodel"), &rig, &why));
  EXPECT_NE(why.find("nothing-camera-0.cameramodel"), std::string::npos) << why;
}

TEST(RigFile, WritingRefusesWhatTheFormatCannotHold) {
  RigFile rig = RadTanRig(2);
  rig.rig.cameras[1].intrinsics.k3 = 0.01;
  std::string why;
  EXPECT_FALSE(WriteRigFile(Temp("k3-camchain.yaml"), CameraFormat::kKalibr, rig, &why));
  EXPECT_NE(why.find("cam1: kalibr: Kalibr's radtan model has k1 k2 r1 r2, no k3"),
            std::string::npos)
      << why;
  rig = RadTanRig(2);
  rig.cam_overlaps = {{1}, {5}};
  EXPECT_FALSE(WriteRigFile(Temp("ov-camchain.yaml"), CameraFormat::kKalibr, rig, &why));
  EXPECT_NE(why.find("cam1.cam_overlaps: 5 is not another camera"), std::string::npos) << why;
  rig = RadTanRig(2);
  rig.rig.cameras[1].cam_from_rig.rotation(2, 2) = -1;
  EXPECT_FALSE(WriteRigFile(Temp("bad.yaml"), CameraFormat::kOpenCv, rig, &why));
  EXPECT_NE(why.find("cam1: cam_from_rig:"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
