// calibrate --images on real images (CTest label "data"): OpenCV's sample chessboards (bundled,
// data/opencv-left) against the published figures and OpenCV's own optimum; rendered folders with a
// known answer; bad folders and targets. Bouguet's example (../shared/data) is in
// shared_data_test.cc.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "bench/app/calibrate.h"
#include "bench/app/image_points.h"
#include "bench/config/target_io.h"
#include "core/random.h"
#include "core/render.h"
#include "core/synthetic.h"
#include "tests/common/calibrate_folder.h"
#include "tests/common/rendered_folder.h"
#include "tests/common/test_data.h"

namespace calibench {
namespace {

// OpenCV's samples/data left01..14 (9 x 6 inner corners). Reference: OpenCV's own procedure
// (findChessboardCorners, cornerSubPix 5x5, calibrateCamera flags 0 = 5 distortion terms) in
// OpenCV 4.10 / 5.0 (SOURCE.md): fx 532.789, fy 532.914, cx 342.481, cy 233.913, k1 -0.281102,
// rms 0.19624. Debian's OpenCV 4.6 finds the corners slightly differently: we allow 0.05 px on
// the focal lengths and 0.1 px on the centre (a tenth of a standard deviation), 0.002 on k1.
TEST(CalibrateImages, OpenCvLeftMatchesOpenCvsPublishedResult) {
  ImageFolderReport images;
  const CalibrateReport r = CalibrateFolder(BundledData("opencv-left"),
                                            "target_type: 'checkerboard'\ntargetCols: 9\n"
                                            "targetRows: 6\nrowSpacingMeters: 0.025\n"
                                            "colSpacingMeters: 0.025\n",
                                            LensModel::kPinholeRadTan5, &images);
  ASSERT_TRUE(r.IsUsable()) << r.ceres.message;
  EXPECT_EQ(images.used, 13);
  const CameraIntrinsics& k = r.ceres.intrinsics;
  EXPECT_NEAR(k.fku_px, 532.789, 0.05);
  EXPECT_NEAR(k.fkv_px, 532.914, 0.05);
  EXPECT_NEAR(k.u0_px, 342.481, 0.1);
  EXPECT_NEAR(k.v0_px, 233.913, 0.1);
  EXPECT_NEAR(k.k1, -0.281102, 0.002);
  EXPECT_NEAR(r.ceres.rms_reproj_px, 0.19624, 0.002);
  EXPECT_NEAR(k.fku_px, r.zhang.intrinsics.fku_px, kSameOptimumPx);
  EXPECT_NEAR(k.u0_px, r.zhang.intrinsics.u0_px, kSameOptimumPx);
}

// The whole chain on images with a known answer: a Kalibr AprilGrid (2-bit border) rendered from
// 12 viewpoints by a
// distorted camera (k1 = -0.1, k2 = 0.02), 1 gray level of noise, written as PNG, then
// calibrate --images. Corner errors of ~0.03 px over 12 x 144 corners put the focal lengths'
// standard deviation near 0.05 px; we allow 0.5 px (10 sigma, room for any residual bias of the
// straight-edge refinement under distortion), 0.5 px on the centre and 0.005 on k1.
TEST(CalibrateImages, RenderedAprilGridRecoversTheCamera) {
  const CameraIntrinsics truth{600, 605, 90, 322, 238, -0.1, 0.02};
  AprilGrid grid;
  grid.tag_size_m = 0.03;
  grid.black_tag_border = 2;  // Kalibr's printed layout: the target YAML's default.
  const std::string dir = testing::TempDir() + "/rendered_grid";
  const int written = WriteRenderedAprilGridFolder(dir, truth, grid, RenderedFolderOptions());
  ASSERT_EQ(written, 12);
  ImageFolderReport images;
  const CalibrateReport r = CalibrateFolder(
      dir,
      "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 6\ntagSize: 0.03\ntagSpacing: 0.3\n"
      "cornerSquares: false\n",  // calibench's renderer draws none.
      LensModel::kPinholeK2, &images);
  ASSERT_TRUE(r.IsUsable()) << r.ceres.message;
  EXPECT_EQ(images.used, 12);
  EXPECT_EQ(images.tags_detected, 12 * 36);
  const CameraIntrinsics& k = r.ceres.intrinsics;
  EXPECT_NEAR(k.fku_px, truth.fku_px, 0.5);
  EXPECT_NEAR(k.fkv_px, truth.fkv_px, 0.5);
  EXPECT_NEAR(k.u0_px, truth.u0_px, 0.5);
  EXPECT_NEAR(k.v0_px, truth.v0_px, 0.5);
  EXPECT_NEAR(k.k1, truth.k1, 0.005);
  std::printf("rendered aprilgrid: f (%.3f, %.3f), c (%.3f, %.3f), k1 %.5f, k2 %.5f, rms %.4f px\n",
              k.fku_px, k.fkv_px, k.u0_px, k.v0_px, k.k1, k.k2, r.ceres.rms_reproj_px);
}

TEST(CalibrateImages, BadFoldersAndTargetsGiveClearErrors) {
  CalibrationTarget target;
  std::string why;
  EXPECT_FALSE(
      LoadTargetYaml(WriteTarget("bad1.yaml", "target_type: 'circlegrid'\n"), &target, &why));
  EXPECT_NE(why.find("target_type"), std::string::npos) << why;
  EXPECT_FALSE(LoadTargetYaml(
      WriteTarget("bad2.yaml", "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\n"),
      &target, &why));
  EXPECT_NE(why.find("tagSpacing: missing"), std::string::npos) << why;
  EXPECT_FALSE(LoadTargetYaml(WriteTarget("bad3.yaml",
                                          "target_type: checkerboard\ntargetCols: 9\n"
                                          "targetRows: 6\nrowSpacingMeters: 0.02\n"
                                          "colSpacingMeter: 0.02\n"),
                              &target, &why));
  EXPECT_NE(why.find("colSpacingMeter"), std::string::npos) << why;

  const std::string empty = testing::TempDir() + "/empty_images";
  std::filesystem::remove_all(empty);
  std::filesystem::create_directories(empty);
  ASSERT_TRUE(LoadTargetYaml(WriteTarget("ok.yaml",
                                         "target_type: checkerboard\ntargetCols: 9\n"
                                         "targetRows: 6\nrowSpacingMeters: 0.02\n"
                                         "colSpacingMeters: 0.02\n"),
                             &target, &why))
      << why;
  PointData data;
  ImageFolderReport report;
  std::vector<int> used;
  EXPECT_FALSE(LoadImagePoints(empty, target, &data, &report, &used, &why));
  EXPECT_NE(why.find("no images"), std::string::npos) << why;
  // A zero-byte and a truncated "image" are listed as unreadable, and nothing is found.
  std::ofstream(empty + "/zero.png");
  std::ofstream(empty + "/truncated.jpg") << "\xff\xd8\xff\xe0 not really a jpeg";
  EXPECT_FALSE(LoadImagePoints(empty, target, &data, &report, &used, &why));
  ASSERT_EQ(report.images.size(), 2u);
  for (const ImageResult& r : report.images) {
    EXPECT_FALSE(r.used);
    EXPECT_NE(r.reason.find("unreadable"), std::string::npos) << r.reason;
  }
  EXPECT_NE(why.find("none of 2 images"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
