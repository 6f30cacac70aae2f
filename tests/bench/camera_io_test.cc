// Camera files (bench/config/camera_io.h): exact round trips through opencv, kalibr and mrcal,
// mrcal's own projection of our .cameramodel against ours, and the refusals with their reasons.
#include "bench/config/camera_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace calibench {
namespace {

// The formats write 17 significant digits, so a round trip is exact; the bar is 1e-9.
constexpr double kRoundTripRelTol = 1e-9;
// mrcal and calibench evaluate the same OpenCV polynomial in a different order of operations:
// ~1e-13 px apart at 1000 px; the bar is 1e-6 px.
constexpr double kMrcalAgreementPx = 1e-6;

std::string Temp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

CameraFile Radtan(LensModel model) {
  CameraFile camera;
  camera.intrinsics = {812.123456789012, 805.987654321098, 90.0,   318.5,   236.25,
                       -0.2513,          0.0712,           1.2e-3, -2.3e-4, 0.0};
  if (model == LensModel::kPinholeRadTan5) camera.intrinsics.k3 = 0.0131;
  if (model == LensModel::kPinholeK2) camera.intrinsics.p1 = camera.intrinsics.p2 = 0;
  camera.lens_model = model;
  camera.image_width = 640;
  camera.image_height = 480;
  camera.rms_reproj_px = 0.1875;
  camera.intrinsics_std.fill(std::nan(""));
  return camera;
}

CameraFile Fisheye() {
  CameraFile camera;
  CameraIntrinsics& k = camera.intrinsics;
  k.family = LensFamily::kEquidistant;
  k.fku_px = 190.97847715128717, k.fkv_px = 190.9733070521226;
  k.u0_px = 254.93170605935475, k.v0_px = 256.8974428996504;
  k.k1 = 0.0034823894022493434, k.k2 = 0.0007150348452162257;
  k.k3 = -0.0020532361418706202, k.k4 = 0.00020293673591811182;
  camera.lens_model = LensModel::kPinholeEqui;
  camera.image_width = camera.image_height = 512;
  camera.intrinsics_std.fill(std::nan(""));
  return camera;
}

void ExpectSameCamera(const CameraFile& a, const CameraFile& b, const std::string& what) {
  EXPECT_EQ(a.intrinsics.family, b.intrinsics.family) << what;
  const auto pa = a.intrinsics.Params(), pb = b.intrinsics.Params();
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(pa[i], pb[i], kRoundTripRelTol * std::max(1.0, std::abs(pa[i])))
        << what << ": " << ParamNames(a.intrinsics.family)[i];
  }
  EXPECT_EQ(a.image_width, b.image_width) << what;
  EXPECT_EQ(a.image_height, b.image_height) << what;
  EXPECT_EQ(a.lens_model, b.lens_model) << what;
  EXPECT_EQ(a.estimate_skew, b.estimate_skew) << what;
}

TEST(CameraFile, EveryFormatRoundTripsEveryCameraItCanHold) {
  const struct {
    CameraFile camera;
    CameraFormat format;
    const char* file;
  } cases[] = {
      {Radtan(LensModel::kPinholeRadTan5), CameraFormat::kOpenCv, "a.yaml"},
      {Radtan(LensModel::kPinholeRadTan4), CameraFormat::kOpenCv, "b.xml"},
      {Fisheye(), CameraFormat::kOpenCv, "c.yaml"},
      {Radtan(LensModel::kPinholeRadTan4), CameraFormat::kKalibr, "d-camchain.yaml"},
      {Fisheye(), CameraFormat::kKalibr, "e-camchain.yaml"},
      {Radtan(LensModel::kPinholeK2), CameraFormat::kMrcal, "f.cameramodel"},
      {Radtan(LensModel::kPinholeRadTan4), CameraFormat::kMrcal, "g.cameramodel"},
      {Radtan(LensModel::kPinholeRadTan5), CameraFormat::kMrcal, "h.cameramodel"},
  };
  for (const auto& c : cases) {
    const std::string path = Temp(c.file);
    std::string why;
    ASSERT_TRUE(WriteCameraFile(path, c.format, c.camera, &why)) << why;
    EXPECT_EQ(CameraFormatFromPath(path), c.format) << c.file;
    CameraFile back;
    ASSERT_TRUE(ReadCameraFile(path, &back, &why)) << why;
    ExpectSameCamera(c.camera, back, c.file);
  }
  // The opencv file also keeps skew, standard deviations and per-view RMS.
  CameraFile skewed = Radtan(LensModel::kPinholeRadTan4);
  skewed.intrinsics.phi_deg = 89.87654321;
  skewed.estimate_skew = true;
  skewed.intrinsics_std[0] = 1.25, skewed.intrinsics_std[2] = 1e-4;
  skewed.view_rms_px = {0.1, 0.2};
  CameraFile back;
  std::string why;
  ASSERT_TRUE(WriteCameraFile(Temp("skew.yaml"), CameraFormat::kOpenCv, skewed, &why)) << why;
  ASSERT_TRUE(ReadCameraFile(Temp("skew.yaml"), &back, &why)) << why;
  ExpectSameCamera(skewed, back, "skew.yaml");
  EXPECT_EQ(back.intrinsics_std[0], 1.25);
  EXPECT_NEAR(back.intrinsics_std[2], 1e-4, 1e-4 * kRoundTripRelTol);
  EXPECT_TRUE(std::isnan(back.intrinsics_std[1]));
  EXPECT_EQ(back.view_rms_px, skewed.view_rms_px);
}

TEST(CameraFile, CamerasAFormatCannotHoldAreRefusedWithTheReason) {
  CameraFile skewed = Radtan(LensModel::kPinholeRadTan4);
  skewed.intrinsics.phi_deg = 89.5;
  CameraFile k3 = Radtan(LensModel::kPinholeRadTan5);
  const struct {
    CameraFile camera;
    CameraFormat format;
    const char* reason;
  } cases[] = {{skewed, CameraFormat::kKalibr, "no skew"},
               {skewed, CameraFormat::kMrcal, "no skew"},
               {k3, CameraFormat::kKalibr, "no k3"},
               {Fisheye(), CameraFormat::kMrcal, "no Kannala-Brandt"}};
  for (const auto& c : cases) {
    std::string why;
    const std::string path = Temp("refused.out");
    EXPECT_FALSE(WriteCameraFile(path, c.format, c.camera, &why));
    EXPECT_NE(why.find(c.reason), std::string::npos) << why;
    EXPECT_NE(why.find(path), std::string::npos) << why;
    EXPECT_FALSE(std::filesystem::exists(path)) << "nothing half-written";
  }
}

TEST(CameraFile, BadFilesAreRefusedNamingTheFieldAndReason) {
  const struct {
    const char* file;
    const char* text;
    const char* reason;
  } cases[] = {
      {"cahvor.cameramodel",
       "{ 'lensmodel': 'LENSMODEL_CAHVOR', 'intrinsics': [1, 1, 1, 1, 0, 0, 0, 0, 0],\n"
       "  'imagersize': [640, 480] }\n",
       "lensmodel: 'LENSMODEL_CAHVOR' has no calibench counterpart"},
      {"short.cameramodel",
       "{ 'lensmodel': 'LENSMODEL_OPENCV4', 'intrinsics': [800, 800, 320], 'imagersize': [640, "
       "480] }\n",
       "intrinsics: LENSMODEL_OPENCV4 has 8 values, got 3"},
      {"rational.cameramodel",
       "{ 'lensmodel': 'LENSMODEL_OPENCV8', 'intrinsics': [800, 800, 320, 240, 0, 0, 0, 0, 0, "
       "0.1, 0, 0], 'imagersize': [640, 480] }\n",
       "rational terms k4..k6 must be 0"},
      {"omni-camchain.yaml",
       "cam0:\n  camera_model: omni\n  intrinsics: [1, 2, 3, 4, 5]\n  resolution: [640, 480]\n",
       "camera_model: 'omni' is not supported"},
      {"k5-camchain.yaml",
       "cam0:\n  camera_model: pinhole\n  intrinsics: [800, 800, 320, 240]\n"
       "  distortion_model: equidistant\n  distortion_coeffs: [0.1, 0.01, 0, 0, 0.001]\n"
       "  resolution: [640, 480]\n",
       "distortion_coeffs: expected a list of 4 numbers"},
      {"fov-camchain.yaml",
       "cam0:\n  camera_model: pinhole\n  intrinsics: [800, 800, 320, 240]\n"
       "  distortion_model: fov\n  distortion_coeffs: [0.9]\n  resolution: [640, 480]\n",
       "distortion_model: 'fov' is not supported"},
  };
  for (const auto& c : cases) {
    const std::string path = Temp(c.file);
    std::ofstream(path) << c.text;
    CameraFile camera;
    std::string why;
    EXPECT_FALSE(ReadCameraFile(path, &camera, &why)) << c.file;
    EXPECT_NE(why.find(c.reason), std::string::npos) << why;
    EXPECT_EQ(why.rfind(path, 0), 0u) << why;
  }
  // An OpenCV fisheye file with five coefficients.
  CameraFile fisheye = Fisheye();
  std::string why;
  ASSERT_TRUE(WriteCameraFile(Temp("fish.yaml"), CameraFormat::kOpenCv, fisheye, &why));
  std::ifstream in(Temp("fish.yaml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t at = text.find("cols: 4");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 7, "cols: 5");
  const size_t data = text.find("]", text.find("distortion_coefficients"));
  text.insert(data, ", 0.001");
  std::ofstream(Temp("fish5.yaml")) << text;
  CameraFile camera;
  EXPECT_FALSE(ReadCameraFile(Temp("fish5.yaml"), &camera, &why));
  EXPECT_NE(why.find("the equidistant model has 4 (k1..k4), got 5"), std::string::npos) << why;
}

// Debian's mrcal (python3-mrcal) loads our .cameramodel and projects points where we do.
TEST(CameraFile, MrcalProjectsOurCameraModelWhereWeDo) {
  for (LensModel model : {LensModel::kPinhole, LensModel::kPinholeK2, LensModel::kPinholeRadTan4,
                          LensModel::kPinholeRadTan5}) {
    CameraFile camera = Radtan(model);
    if (model == LensModel::kPinhole) {
      CameraIntrinsics& k = camera.intrinsics;
      k.k1 = k.k2 = k.p1 = k.p2 = k.k3 = 0;
    }
    const std::string model_path = Temp("mrcal_check.cameramodel");
    const std::string points_path = Temp("mrcal_points.txt");
    std::string why;
    ASSERT_TRUE(WriteCameraFile(model_path, CameraFormat::kMrcal, camera, &why)) << why;
    std::ofstream points(points_path);
    points.precision(17);
    int n = 0;
    for (double x = -0.6; x <= 0.6; x += 0.15) {
      for (double y = -0.45; y <= 0.45; y += 0.15) {
        const Eigen::Vector3d p(x * 2.0, y * 2.0, 2.0);
        Eigen::Vector2d pixel;
        ASSERT_TRUE(ProjectPoint(camera.intrinsics, p, &pixel));
        points << p.x() << " " << p.y() << " " << p.z() << " " << pixel.x() << " " << pixel.y()
               << "\n";
        ++n;
      }
    }
    points.close();
    const std::string script =
        "import sys, numpy, mrcal\n"
        "m = mrcal.cameramodel(sys.argv[1])\n"
        "d = numpy.loadtxt(sys.argv[2])\n"
        "q = mrcal.project(d[:, :3], *m.intrinsics())\n"
        "err = numpy.max(numpy.abs(q - d[:, 3:]))\n"
        "print(m.intrinsics()[0], len(d), err)\n"
        "sys.exit(0 if err < float(sys.argv[3]) else 1)\n";
    std::ofstream(Temp("mrcal_check.py")) << script;
    const std::string command = "/usr/bin/python3 " + Temp("mrcal_check.py") + " " + model_path +
                                " " + points_path + " " + std::to_string(kMrcalAgreementPx) +
                                " > " + Temp("mrcal_out.txt") + " 2>&1";
    const int status = std::system(command.c_str());
    std::ifstream out(Temp("mrcal_out.txt"));
    std::string output((std::istreambuf_iterator<char>(out)), std::istreambuf_iterator<char>());
    EXPECT_EQ(status, 0) << ToString(model) << ": " << output
                         << "(needs Debian's python3-mrcal; scripts/test installs it)";
    EXPECT_NE(output.find(std::to_string(n)), std::string::npos) << output;
  }
}

}  // namespace
}  // namespace calibench
