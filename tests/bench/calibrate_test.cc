// Regression on published calibration data (CTest label "data"): OpenCV's calib1.dat, bundled in
// data/opencv-calib1. Zhang's points (../shared/data, not bundled) are in shared_data_test.cc.
#include "bench/app/calibrate.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>

#include "tests/common/test_data.h"

namespace calibench {
namespace {

// OpenCV's regression file carries Bouguet's toolbox results (k1 k2 p1 p2 model).
TEST(CalibrateFromPoints, OpenCvCalib1MatchesItsReference) {
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(BundledData("opencv-calib1/calib1.dat"), &data, &why)) << why;
  ASSERT_EQ(data.views.size(), 7u);
  ASSERT_TRUE(data.reference.has_value());
  CalibrateOptions options;
  options.model = LensModel::kPinholeRadTan4;
  const CalibrateReport report = CalibrateFromPoints(data, options);
  ASSERT_TRUE(report.IsUsable()) << report.ceres.message;
  const CameraIntrinsics &k = report.ceres.intrinsics, &ref = *data.reference;
  // The file prints 8 significant digits for A and 5 decimals for distortion.
  EXPECT_NEAR(k.fku_px, ref.fku_px, 1e-5 * ref.fku_px);
  EXPECT_NEAR(k.fkv_px, ref.fkv_px, 1e-5 * ref.fkv_px);
  EXPECT_NEAR(k.u0_px, ref.u0_px, 1e-5 * ref.u0_px);
  EXPECT_NEAR(k.v0_px, ref.v0_px, 1e-5 * ref.v0_px);
  for (const auto& [ours, theirs] :
       {std::pair{k.k1, ref.k1}, {k.k2, ref.k2}, {k.p1, ref.p1}, {k.p2, ref.p2}}) {
    EXPECT_NEAR(ours, theirs, 1e-4);
  }
  // Ceres and OpenCV minimise the same cost: the same optimum.
  EXPECT_NEAR(k.fku_px, report.zhang.intrinsics.fku_px, 1e-3);
}

TEST(CalibrateFromPoints, CameraYamlIsReadableByOpenCv) {
  CameraFile camera;
  camera.intrinsics = {800, 790, 89, 320, 240, -0.1, 0.02, 1e-3, -1e-3, 0.0};
  camera.intrinsics_std.fill(std::nan(""));
  camera.intrinsics_std[0] = 1.5;
  camera.image_width = 640;
  camera.image_height = 480;
  camera.rms_reproj_px = 0.25;
  camera.model = "pinhole-radtan4+skew";
  const std::string path = ::testing::TempDir() + "/camera.yaml";
  std::string why;
  ASSERT_TRUE(WriteCameraYaml(path, camera, &why)) << why;
  cv::FileStorage fs(path, cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  cv::Mat a, d;
  fs["camera_matrix"] >> a;
  fs["distortion_coefficients"] >> d;
  EXPECT_NEAR(a.at<double>(0, 0), 800, 1e-9);
  EXPECT_NEAR(a.at<double>(0, 1), camera.intrinsics.Matrix()(0, 1), 1e-9);
  EXPECT_NEAR(d.at<double>(2), 1e-3, 1e-15);
  EXPECT_EQ(static_cast<int>(fs["image_width"]), 640);
  EXPECT_EQ(static_cast<double>(fs["rms_reproj_px"]), 0.25);
  EXPECT_EQ(static_cast<double>(fs["std_fku_px"]), 1.5);
  EXPECT_TRUE(fs["std_fkv_px"].empty());  // Not estimated: not written.
}

TEST(LoadPointData, BadPathsAreNamed) {
  PointData data;
  std::string why;
  EXPECT_FALSE(LoadPointData("/nonexistent/points", &data, &why));
  EXPECT_NE(why.find("/nonexistent/points"), std::string::npos);
  const std::string empty_dir = ::testing::TempDir() + "/empty_points";
  std::filesystem::create_directories(empty_dir);
  EXPECT_FALSE(LoadPointData(empty_dir, &data, &why));
  EXPECT_NE(why.find("Model.txt"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
