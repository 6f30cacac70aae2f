// Camera files (io/camera_io.h): exact round trips through opencv, kalibr and mrcal,
// mrcal's own projection of our .cameramodel against ours, and the refusals with their reasons.
#include "io/camera_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/ccalib/omnidir.hpp>
#include <opencv2/core.hpp>
#include <sstream>

namespace calibench {
namespace {

// The formats write 17 significant digits, so a round trip is exact; the bar is 1e-9.
constexpr double kRoundTripRelTol = 1e-9;
// mrcal and calibench evaluate the same OpenCV polynomial in a different order of operations:
// ~1e-13 px apart at 1000 px; the bar is 1e-6 px.
constexpr double kMrcalAgreementPx = 1e-6;
// cv::omnidir and calibench evaluate Mei's model in another order: ~1e-13 px apart (measured).
constexpr double kOmnidirAgreementPx = 1e-9;

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

// The omnidirectional families (TUM VI-like 512 x 512 lenses, basalt's published values rounded).
CameraFile Omni(LensFamily family) {
  CameraFile camera;
  CameraIntrinsics& k = camera.intrinsics;
  k.family = family;
  k.fku_px = 190.53721234567891, k.fkv_px = 190.47312345678912;
  k.u0_px = 254.93170605935475, k.v0_px = 256.8974428996504;
  switch (family) {
    case LensFamily::kUnified:
      k.fku_px *= 1.8, k.fkv_px *= 1.8;
      k.xi = 0.8123456789012345, k.k1 = -0.0412345678901234, k.k2 = 0.0071234567890123;
      k.p1 = 1.2345678901234e-4, k.p2 = -2.3456789012345e-4;
      camera.lens_model = LensModel::kUnified;
      break;
    case LensFamily::kEucm:
      k.alpha = 0.6291234567890123, k.beta = 1.0418765432109876;
      camera.lens_model = LensModel::kEucm;
      break;
    case LensFamily::kDoubleSphere:
      k.fku_px *= 0.82, k.fkv_px *= 0.82;
      k.xi = -0.1812345678901234, k.alpha = 0.5912345678901234;  // xi < 0, as TUM VI fits.
      camera.lens_model = LensModel::kDoubleSphere;
      break;
    case LensFamily::kRadTan:
    case LensFamily::kEquidistant:
      break;
  }
  camera.image_width = camera.image_height = 512;
  camera.rms_reproj_px = 0.0925;
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
      {Omni(LensFamily::kUnified), CameraFormat::kOpenCv, "i.yaml"},
      {Omni(LensFamily::kEucm), CameraFormat::kOpenCv, "j.xml"},
      {Omni(LensFamily::kDoubleSphere), CameraFormat::kOpenCv, "k.json"},
      {Omni(LensFamily::kUnified), CameraFormat::kKalibr, "l-camchain.yaml"},
      {Omni(LensFamily::kEucm), CameraFormat::kKalibr, "m-camchain.yaml"},
      {Omni(LensFamily::kDoubleSphere), CameraFormat::kKalibr, "n-camchain.yaml"},
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
  } cases[] = {
      {skewed, CameraFormat::kKalibr, "no skew"},
      {skewed, CameraFormat::kMrcal, "no skew"},
      {k3, CameraFormat::kKalibr, "no k3"},
      {Fisheye(), CameraFormat::kMrcal, "no Kannala-Brandt"},
      {Omni(LensFamily::kUnified), CameraFormat::kMrcal, "mrcal 2.2 has no unified (Mei)"},
      {Omni(LensFamily::kEucm), CameraFormat::kMrcal, "mrcal 2.2 has no eucm"},
      {Omni(LensFamily::kDoubleSphere), CameraFormat::kMrcal, "mrcal 2.2 has no double-sphere"}};
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
      {"kb4-camchain.yaml",
       "cam0:\n  camera_model: kb4\n  intrinsics: [1, 2, 3, 4, 5]\n  resolution: [640, 480]\n",
       "camera_model: 'kb4' is not a Kalibr camera model calibench reads"},
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
  const size_t data = text.find(']', text.find("distortion_coefficients"));
  text.insert(data, ", 0.001");
  std::ofstream(Temp("fish5.yaml")) << text;
  CameraFile camera;
  EXPECT_FALSE(ReadCameraFile(Temp("fish5.yaml"), &camera, &why));
  EXPECT_NE(why.find("the equidistant model has 4 (k1..k4), got 5"), std::string::npos) << why;
}

// The text after `key: ` on its line of a camchain (the writer puts lists in flow style).
std::string Field(const std::string& text, const std::string& key) {
  const size_t at = text.find(key + ": ");
  if (at == std::string::npos) return "";
  const size_t begin = at + key.size() + 2;
  return text.substr(begin, text.find('\n', begin) - begin);
}

// The numbers of a flow list "[a, b, c]".
std::vector<double> Numbers(std::string list) {
  std::replace(list.begin(), list.end(), ',', ' ');
  std::replace(list.begin(), list.end(), '[', ' ');
  std::replace(list.begin(), list.end(), ']', ' ');
  std::istringstream in(list);
  std::vector<double> values;
  for (double v; in >> v;) values.push_back(v);
  return values;
}

// The omnidirectional families' files: the opencv file keeps their standard deviations under
// their parameters' names, the Kalibr camchain has Kalibr's orders ([xi, fu, fv, pu, pv] for omni
// with radtan, [alpha, beta, fu, ..] for eucm, [xi, alpha, fu, ..] for ds, distortion none).
// Mutation caught: Kalibr's eucm intrinsics written [beta, alpha, ..] (the round trip alone, which
// reads in the same order, passes).
TEST(CameraFile, OmnidirectionalFilesHoldKalibrsOrdersAndTheStandardDeviations) {
  CameraFile ds = Omni(LensFamily::kDoubleSphere);
  ds.intrinsics_std[0] = 0.21, ds.intrinsics_std[5] = 0.0031, ds.intrinsics_std[6] = 0.0012;
  std::string why;
  ASSERT_TRUE(WriteCameraFile(Temp("ds_std.yaml"), CameraFormat::kOpenCv, ds, &why)) << why;
  CameraFile back;
  ASSERT_TRUE(ReadCameraFile(Temp("ds_std.yaml"), &back, &why)) << why;
  EXPECT_EQ(back.intrinsics_std[5], 0.0031);  // std_xi.
  EXPECT_EQ(back.intrinsics_std[6], 0.0012);  // std_alpha.
  EXPECT_TRUE(std::isnan(back.intrinsics_std[7]));
  const struct {
    LensFamily family;
    const char* camera_model;
    const char* distortion_model;
    std::vector<double> intrinsics;
    size_t coefficients;
  } kalibr[] = {
      {LensFamily::kUnified, "omni", "radtan", {0.8123456789012345, 1.8 * 190.53721234567891}, 4},
      {LensFamily::kEucm,
       "eucm",
       "none",
       {0.6291234567890123, 1.0418765432109876, 190.53721234567891},
       0},
      {LensFamily::kDoubleSphere,
       "ds",
       "none",
       {-0.1812345678901234, 0.5912345678901234, 0.82 * 190.53721234567891},
       0},
  };
  for (const auto& c : kalibr) {
    const std::string path = Temp(std::string(c.camera_model) + "-camchain.yaml");
    ASSERT_TRUE(WriteCameraFile(path, CameraFormat::kKalibr, Omni(c.family), &why)) << why;
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(Field(text, "camera_model"), c.camera_model);
    EXPECT_EQ(Field(text, "distortion_model"), c.distortion_model);
    EXPECT_EQ(Numbers(Field(text, "distortion_coeffs")).size(), c.coefficients);
    const std::vector<double> intrinsics = Numbers(Field(text, "intrinsics"));
    ASSERT_EQ(intrinsics.size(), c.intrinsics.size() + 3) << c.camera_model;
    for (size_t i = 0; i < c.intrinsics.size(); ++i) {
      EXPECT_NEAR(intrinsics[i], c.intrinsics[i], kRoundTripRelTol * std::abs(c.intrinsics[i]))
          << c.camera_model << " " << i;
    }
  }
}

// OpenCV's cv::omnidir projects our unified opencv file (camera_matrix, distortion_coefficients
// k1 k2 p1 p2, xi: its own omni_calibration's fields) where we do; and a file as that sample
// writes it (no distortion_model) reads as unified. The two evaluate Mei's model in another order
// of operations: ~1e-13 px apart; 1e-9 px is room for another libm, not for another model.
// Mutation caught: distortion_coefficients written k1 k2 p2 p1 (1.09 px apart).
TEST(CameraFile, CvOmnidirProjectsOurUnifiedFileWhereWeDo) {
  const CameraFile camera = Omni(LensFamily::kUnified);
  std::string why;
  ASSERT_TRUE(WriteCameraFile(Temp("omnidir.yaml"), CameraFormat::kOpenCv, camera, &why)) << why;
  cv::FileStorage fs(Temp("omnidir.yaml"), cv::FileStorage::READ);
  cv::Mat k, d;
  double xi = 0;
  fs["camera_matrix"] >> k;
  fs["distortion_coefficients"] >> d;
  fs["xi"] >> xi;
  std::vector<cv::Vec3d> points;
  for (double theta = 0.05; theta < 1.7; theta += 0.15) {  // Past 90 deg from the axis.
    for (double azimuth = 0; azimuth < 6.2; azimuth += 0.7) {
      points.emplace_back(std::sin(theta) * std::cos(azimuth), std::sin(theta) * std::sin(azimuth),
                          std::cos(theta));
    }
  }
  std::vector<cv::Vec2d> theirs;
  cv::omnidir::projectPoints(points, theirs, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, xi, d);
  double worst = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d ours;
    ASSERT_TRUE(ProjectPoint(camera.intrinsics,
                             Eigen::Vector3d(points[i][0], points[i][1], points[i][2]), &ours));
    worst = std::max(worst, (ours - Eigen::Vector2d(theirs[i][0], theirs[i][1])).norm());
  }
  std::printf("[ measured ] |ours - cv::omnidir| <= %.2g px over %zu rays\n", worst, points.size());
  EXPECT_LT(worst, kOmnidirAgreementPx);
  // omni_calibration's own output: camera_matrix, distortion_coefficients, xi, no model fields.
  {
    cv::FileStorage out(Temp("omni_sample.yaml"), cv::FileStorage::WRITE);
    out << "camera_matrix" << k << "distortion_coefficients" << d << "xi" << xi;
    out << "image_width" << 512 << "image_height" << 512;
  }
  CameraFile back;
  ASSERT_TRUE(ReadCameraFile(Temp("omni_sample.yaml"), &back, &why)) << why;
  EXPECT_EQ(back.intrinsics.family, LensFamily::kUnified);
  EXPECT_EQ(back.lens_model, LensModel::kUnified);
  EXPECT_NEAR(back.intrinsics.xi, camera.intrinsics.xi, kRoundTripRelTol);
}

// Bad omnidirectional files are refused naming the file, the field and the reason.
// Mutation caught: ReadKalibr without the intrinsics' range check (xi -0.3 accepted, then refused
// by ReadCameraFile without the field's name).
TEST(CameraFile, BadOmnidirectionalFilesAreRefusedNamingTheFieldAndReason) {
  const std::string res = "  resolution: [512, 512]\n";
  const struct {
    const char* file;
    std::string text;
    const char* reason;
  } cases[] = {
      {"xi-camchain.yaml",
       "cam0:\n  camera_model: omni\n  intrinsics: [-0.3, 340, 340, 256, 256]\n" + res,
       "cam0.intrinsics: xi must be >= 0 for the unified model"},
      {"alpha-camchain.yaml",
       "cam0:\n  camera_model: eucm\n  intrinsics: [1.2, 1.0, 190, 190, 256, 256]\n" + res,
       "cam0.intrinsics: alpha must lie in [0, 1] for the eucm model"},
      {"beta-camchain.yaml",
       "cam0:\n  camera_model: eucm\n  intrinsics: [0.6, 0.0, 190, 190, 256, 256]\n" + res,
       "cam0.intrinsics: beta must be > 0 for the eucm model"},
      {"ds5-camchain.yaml",
       "cam0:\n  camera_model: ds\n  intrinsics: [-0.2, 0.6, 156, 156, 256]\n" + res,
       "cam0.intrinsics: expected a list of 6 numbers"},
      {"dsxi-camchain.yaml",
       "cam0:\n  camera_model: ds\n  intrinsics: [-1.5, 0.6, 156, 156, 256, 256]\n" + res,
       "xi must be > -1 for the double-sphere model"},
      {"omni6-camchain.yaml",
       "cam0:\n  camera_model: omni\n  intrinsics: [0.8, 340, 340, 256, 256]\n"
       "  distortion_model: radtan\n  distortion_coeffs: [0.1, 0.01, 0, 0, 0.001]\n" +
           res,
       "cam0.distortion_coeffs: expected a list of 4 numbers"},
      {"omniequi-camchain.yaml",
       "cam0:\n  camera_model: omni\n  intrinsics: [0.8, 340, 340, 256, 256]\n"
       "  distortion_model: equidistant\n  distortion_coeffs: [0.1, 0.01, 0, 0]\n" +
           res,
       "distortion_model: 'equidistant' is not supported with camera_model omni"},
      {"eucmrt-camchain.yaml",
       "cam0:\n  camera_model: eucm\n  intrinsics: [0.6, 1.0, 190, 190, 256, 256]\n"
       "  distortion_model: radtan\n  distortion_coeffs: [0.1, 0.01, 0, 0]\n" +
           res,
       "distortion_model: 'radtan' is not supported with camera_model eucm (none)"},
      {"unified5.yaml",
       "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
       "  data: [340., 0., 256., 0., 340., 256., 0., 0., 1.]\ndistortion_model: unified\n"
       "distortion_coefficients: [0.1, 0.01, 0., 0., 0.001]\nxi: 0.8\nimage_width: 512\n"
       "image_height: 512\n",
       "distortion_coefficients: the unified model has 4 (k1 k2 p1 p2), got 5"},
      {"eucm_nobeta.yaml",
       "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
       "  data: [190., 0., 256., 0., 190., 256., 0., 0., 1.]\ndistortion_model: eucm\n"
       "alpha: 0.6\nimage_width: 512\nimage_height: 512\n",
       "beta: the eucm model needs beta (a number)"},
      {"ds_xi.yaml",
       "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
       "  data: [156., 0., 256., 0., 156., 256., 0., 0., 1.]\ndistortion_model: double-sphere\n"
       "xi: -1.5\nalpha: 0.6\nimage_width: 512\nimage_height: 512\n",
       "xi must be > -1 for the double-sphere model"},
      {"ds_alpha.yaml",
       "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
       "  data: [156., 0., 256., 0., 156., 256., 0., 0., 1.]\ndistortion_model: double-sphere\n"
       "xi: -0.2\nalpha: -0.1\nimage_width: 512\nimage_height: 512\n",
       "alpha must lie in [0, 1] for the double-sphere model"},
      {"ds_model.yaml",
       "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
       "  data: [156., 0., 256., 0., 156., 256., 0., 0., 1.]\ndistortion_model: double-sphere\n"
       "xi: -0.2\nalpha: 0.6\nmodel: eucm\nimage_width: 512\nimage_height: 512\n",
       "model: 'eucm' is not of the double-sphere family"},
  };
  for (const auto& c : cases) {
    const std::string path = Temp(c.file);
    std::ofstream(path) << c.text;
    CameraFile camera;
    std::string why;
    EXPECT_FALSE(ReadCameraFile(path, &camera, &why)) << c.file;
    EXPECT_NE(why.find(c.reason), std::string::npos) << c.file << ": " << why;
    EXPECT_EQ(why.rfind(path, 0), 0u) << why;
  }
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

// A hand-written OpenCV file without its "%YAML:1.0" line (OpenCV's reader refuses it) reads as
// the same camera; an empty file and YAML that is no camera are refused with the reason.
TEST(CameraFile, OpenCvYamlWithoutItsDirectiveLineReads) {
  const std::string with = Temp("directive.yaml");
  std::string why;
  ASSERT_TRUE(
      WriteCameraFile(with, CameraFormat::kOpenCv, Radtan(LensModel::kPinholeRadTan4), &why))
      << why;
  std::ifstream in(with);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(text.rfind("%YAML:1.0\n", 0), 0u);
  const std::string without = Temp("no_directive.yaml");
  std::ofstream(without) << text.substr(10);
  CameraFile a, b;
  ASSERT_TRUE(ReadCameraFile(with, &a, &why)) << why;
  ASSERT_TRUE(ReadCameraFile(without, &b, &why)) << why;
  EXPECT_TRUE(a.intrinsics == b.intrinsics);
  std::ofstream(Temp("empty.yaml")) << "\n";
  EXPECT_FALSE(ReadCameraFile(Temp("empty.yaml"), &b, &why));
  EXPECT_NE(why.find("empty file"), std::string::npos) << why;
  std::ofstream(Temp("notcam.yaml")) << "foo: 1\n";
  EXPECT_FALSE(ReadCameraFile(Temp("notcam.yaml"), &b, &why));
  EXPECT_NE(why.find("camera_matrix"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
