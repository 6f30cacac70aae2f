// Regression on the real data sets that are not bundled (../shared/data, CALIBENCH_DATA_DIR; CTest
// labels "data" and "shared-data"; data/README.md says why): Zhang's published points (no licence
// stated, so not redistributable) and Bouguet's toolbox example (6 MB, no licence stated). Each
// test skips, saying so, only when its folder is absent; CI always has it.
#include <gtest/gtest.h>

#include <cmath>

#include "bench/app/calibrate.h"
#include "tests/common/calibrate_folder.h"
#include "tests/common/test_data.h"

namespace calibench {
namespace {

// Zhang (MSR-TR-98-71), complete calibration with skew and k1, k2, as published:
// alpha 832.5010, beta 832.5309, gamma 0.2046, u0 303.9584, v0 206.5879, k1 -0.228601,
// k2 0.190353. The issue asks for 0.1% on intrinsics and 1% on k1, k2.
TEST(CalibrateFromPoints, ZhangDataMatchesPublishedResults) {
  REQUIRE_SHARED_DATA("zhang");
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(kSharedDataDir + "/zhang", &data, &why)) << why;
  ASSERT_EQ(data.views.size(), 5u);
  ASSERT_EQ(data.views[0].points.size(), 256u);
  CalibrateOptions options;
  options.model = LensModel::kPinholeK2;
  options.estimate_skew = true;
  const CalibrateReport report = CalibrateFromPoints(data, options);
  ASSERT_TRUE(report.IsUsable()) << report.ceres.message;
  const CameraIntrinsics& k = report.ceres.intrinsics;
  constexpr double kIntrinsicsRelTol = 1e-3, kDistortionRelTol = 1e-2;
  EXPECT_NEAR(k.fku_px, 832.5010, kIntrinsicsRelTol * 832.5010);
  EXPECT_NEAR(k.fkv_px, 832.5309, kIntrinsicsRelTol * 832.5309);
  EXPECT_NEAR(k.u0_px, 303.9584, kIntrinsicsRelTol * 303.9584);
  EXPECT_NEAR(k.v0_px, 206.5879, kIntrinsicsRelTol * 206.5879);
  const double gamma = k.Matrix()(0, 1);  // Zhang's skew term.
  EXPECT_NEAR(gamma, 0.2046, 0.01);
  EXPECT_NEAR(k.k1, -0.228601, kDistortionRelTol * 0.228601);
  EXPECT_NEAR(k.k2, 0.190353, kDistortionRelTol * 0.190353);
  // SOURCE.md: the published calibration reprojects with 0.3364 px RMS per point.
  EXPECT_NEAR(report.ceres.rms_reproj_px, 0.3364, 0.001);
  EXPECT_TRUE(std::isfinite(report.ceres.intrinsics_std[0]));
}

// Bouguet's "first calibration example" (13 x 12 inner corners, 30 mm). Published (toolbox web
// page, his clicked corners): fc = [657.463, 657.947], cc = [303.137, 242.569],
// kc = [-0.25403, 0.12143, -0.00021, 0.00002]. Our corners come from OpenCV's detectors, so the
// data differ: SOURCE.md expects ~1 px in f. Tolerances: 2 px on f (0.3%), 2.5 px on the centre
// (about 4 of the published standard deviations), and OpenCV 4.10's result on the same
// detector (fx 656.10, fy 657.01, cx 302.81, cy 244.43) within 0.3 px.
TEST(CalibrateImages, BouguetExampleMatchesPublishedAndOpenCvResults) {
  REQUIRE_SHARED_DATA("bouguet-calib-example");
  ImageFolderReport images;
  const CalibrateReport r = CalibrateFolder(kSharedDataDir + "/bouguet-calib-example",
                                            "target_type: 'checkerboard'\ntargetCols: 13\n"
                                            "targetRows: 12\nrowSpacingMeters: 0.03\n"
                                            "colSpacingMeters: 0.03\n",
                                            LensModel::kPinholeRadTan4, &images);
  ASSERT_TRUE(r.IsUsable()) << r.ceres.message;
  EXPECT_GE(images.used, 19);  // Image18 shows a partial board (SOURCE.md).
  const CameraIntrinsics& k = r.ceres.intrinsics;
  EXPECT_NEAR(k.fku_px, 657.463, 2.0);
  EXPECT_NEAR(k.fkv_px, 657.947, 2.0);
  EXPECT_NEAR(k.u0_px, 303.137, 2.5);
  EXPECT_NEAR(k.v0_px, 242.569, 2.5);
  EXPECT_NEAR(k.fku_px, 656.10, 0.3);
  EXPECT_NEAR(k.fkv_px, 657.01, 0.3);
  EXPECT_NEAR(k.u0_px, 302.81, 0.3);
  EXPECT_NEAR(k.v0_px, 244.43, 0.3);
  EXPECT_NEAR(k.k1, -0.2351, 0.01);
  EXPECT_NEAR(k.fku_px, r.zhang.intrinsics.fku_px, kSameOptimumPx);
}

}  // namespace
}  // namespace calibench
