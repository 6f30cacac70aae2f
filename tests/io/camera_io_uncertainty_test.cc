// The projection covariance in calibench's camera file (io/camera_io.h): written and read back
// exactly, refused with the field and reason when malformed, absent from formats that cannot
// hold it.
#include <gtest/gtest.h>

#include <fstream>

#include "io/camera_io.h"

namespace calibench {
namespace {

std::string Temp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

CameraFile WithCovariance() {
  CameraFile camera;
  camera.intrinsics = {812.5, 805.25, 90.0, 318.5, 236.25, -0.25, 0.07};
  camera.lens_model = LensModel::kPinholeK2;
  camera.image_width = 640, camera.image_height = 480;
  camera.intrinsics_std.fill(std::nan(""));
  // A symmetric positive definite 16 x 16 matrix of distinct entries.
  Eigen::Matrix<double, 16, 16> m;
  for (int r = 0; r < 16; ++r) {
    for (int c = 0; c < 16; ++c) m(r, c) = std::sin(1.0 + r * 16 + c) / (1 + r + c);
  }
  camera.projection.covariance =
      m * m.transpose() + 1e-3 * Eigen::Matrix<double, 16, 16>::Identity();
  camera.projection.sigma_px = 0.2375;
  camera.projection.num_views = 13;
  camera.projection_scale = 1.75;
  return camera;
}

TEST(CameraFileUncertainty, OpenCvFileRoundTripsTheProjectionCovarianceExactly) {
  const CameraFile camera = WithCovariance();
  const std::string path = Temp("with_cov.yaml");
  std::string why;
  ASSERT_TRUE(WriteCameraFile(path, CameraFormat::kOpenCv, camera, &why)) << why;
  CameraFile back;
  ASSERT_TRUE(ReadCameraFile(path, &back, &why)) << why;
  ASSERT_TRUE(back.projection.IsSet());
  // 17 significant digits: exact.
  EXPECT_EQ((back.projection.covariance - camera.projection.covariance).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(back.projection.sigma_px, camera.projection.sigma_px);
  EXPECT_EQ(back.projection.num_views, 13);
  EXPECT_EQ(back.projection_scale, 1.75);
}

TEST(CameraFileUncertainty, FormatsWithoutAPlaceForItReadBackWithout) {
  const CameraFile camera = WithCovariance();
  std::string why;
  for (const auto& [file, format] : {std::make_pair("cov-camchain.yaml", CameraFormat::kKalibr),
                                     std::make_pair("cov.cameramodel", CameraFormat::kMrcal)}) {
    const std::string path = Temp(file);
    ASSERT_TRUE(WriteCameraFile(path, format, camera, &why)) << why;
    CameraFile back;
    ASSERT_TRUE(ReadCameraFile(path, &back, &why)) << why;
    EXPECT_FALSE(back.projection.IsSet()) << file;
  }
}

TEST(CameraFileUncertainty, AMalformedCovarianceIsRefusedNamingTheField) {
  const std::string good = Temp("good_cov.yaml");
  std::string why;
  ASSERT_TRUE(WriteCameraFile(good, CameraFormat::kOpenCv, WithCovariance(), &why)) << why;
  std::ifstream in(good);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // 15 rows instead of 16.
  std::string bad = text;
  const size_t rows = bad.find("rows: 16", bad.find("projection_covariance"));
  ASSERT_NE(rows, std::string::npos);
  bad.replace(rows, 8, "rows: 15");
  const std::string path = Temp("bad_cov.yaml");
  std::ofstream(path) << bad;
  CameraFile camera;
  EXPECT_FALSE(ReadCameraFile(path, &camera, &why));
  EXPECT_NE(why.find("projection_covariance"), std::string::npos) << why;
  EXPECT_EQ(why.rfind(path, 0), 0u) << why;
  // A scale below 1 (the jackknife only ever enlarges it).
  std::string small = text;
  const size_t scale = small.find("projection_scale: ");
  ASSERT_NE(scale, std::string::npos);
  small.replace(scale + 18, 4, "0.50");  // Was 1.75.
  std::ofstream(path) << small;
  EXPECT_FALSE(ReadCameraFile(path, &camera, &why));
  EXPECT_NE(why.find("projection_scale"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
