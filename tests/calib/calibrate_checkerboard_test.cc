// calibrate --images on checkerboards rendered through lenses (sim/checkerboard_image.h) with a
// known answer: cornerSubPix's corners, then the X-junctions re-fitted through each estimate of the
// lens (IterateCornersThroughTheLens, detect/x_junction.h).
#include <gtest/gtest.h>

#include "calib/calibrate.h"
#include "calib/image_points.h"
#include "io/target_io.h"
#include "tests/common/calibrate_folder.h"
#include "tests/common/rendered_folder.h"

namespace calibench {
namespace {

// 24 views of a 9 x 6 board of 3 cm squares, 2 gray levels of noise, sharp and with a 1 px PSF:
// an EuRoC-like lens (k1 = -0.28, k2 = 0.074, 752 x 480, f 458 px, boards at 0.45-0.6 m) and an
// equidistant fisheye (f 230 px, boards at 0.2-0.3 m, up to ~50 deg off axis). Measured, |error| /
// reported std of f.ku, f.kv, u0, v0: with cornerSubPix's corners up to 1.2 (EuRoC-like, blurred)
// and 6.9 (fisheye, blurred): the bent edges bias cornerSubPix, and the fisheye's boards are found
// only by the sector-based detector, whose corners are worse; re-fitted as X-junctions through
// the estimate, at most 2.20 blurred (the EuRoC-like f.kv) and 1.75 sharp (the sharp fisheye's
// v0: sharp frames keep the pixel-phase error of a gradient-based corner, x_junction_test.cc,
// correlated between a view's neighbouring corners).
// kWithinStd = 3: 16 checks, 0.04 expected outside by chance if the stds are right.
constexpr double kWithinStd = 3.0;
// The case this exists for: on the blurred fisheye cornerSubPix's f.ku is off by more than this
// many stds (measured 6.2; 6.3 with another draw of the image noise). On the blurred EuRoC-like
// lens its error is not told apart from its noise (measured 1.1 std; 4.7 with the other draw):
// reported, not asserted.
constexpr double kBiasedBeforeStd = 3.0;

struct LensCase {
  const char* name;
  CameraIntrinsics truth;
  LensModel model;
  RenderedFolderOptions folder;
};

TEST(CalibrateCheckerboard, DistortedViewsAreCalibratedThroughTheLens) {
  CameraIntrinsics fisheye{230.0, 229.0, 90.0, 375.0, 241.0, -0.01, 0.002};
  fisheye.family = LensFamily::kEquidistant;
  RenderedFolderOptions euroc_folder;
  euroc_folder.views = 24, euroc_folder.width = 752, euroc_folder.height = 480;
  euroc_folder.noise_sigma_gray = 2.0;
  euroc_folder.lateral_m = 0.16;
  RenderedFolderOptions fisheye_folder = euroc_folder;
  fisheye_folder.min_distance_m = 0.2, fisheye_folder.max_distance_m = 0.3;
  fisheye_folder.lateral_m = 0.2;
  const std::vector<LensCase> cases = {
      {"euroc-like",
       {458.0, 457.0, 90.0, 367.0, 248.0, -0.28, 0.074},
       LensModel::kPinholeK2,
       euroc_folder},
      {"fisheye", fisheye, LensModel::kPinholeEqui, fisheye_folder},
  };
  CheckerboardPattern pattern;
  CalibrationTarget target;
  std::string why;
  ASSERT_TRUE(LoadTargetYaml(WriteTarget("checkerboard.yaml", CheckerboardTargetYaml(9, 6, 0.03)),
                             &target, &why))
      << why;
  for (const LensCase& c : cases) {
    for (const double blur : {0.0, 1.0}) {
      RenderedFolderOptions folder = c.folder;
      folder.blur_sigma_px = blur;
      const std::string label = std::string(c.name) + ", blur " + std::to_string(blur);
      const std::string dir = testing::TempDir() + "/checkerboard_" + c.name + std::to_string(blur);
      ASSERT_EQ(WriteRenderedCheckerboardFolder(dir, c.truth, pattern, folder), folder.views);
      const FolderCalibration fit = CalibrateFolderThroughTheLens(dir, target, c.model, 4);
      const CalibrateReport& first = fit.first;
      const CalibrateReport& r = fit.last.report;
      std::printf("%s: %d views\n%s", label.c_str(), fit.last.images.used, fit.log.c_str());
      ASSERT_TRUE(r.IsUsable()) << label;
      const std::array<int, 4> slot = {0, 1, 3, 4};  // fku, fkv, (phi), u0, v0 in the raw order.
      const IntrinsicsArray want = c.truth.Params();
      const IntrinsicsArray got = r.ceres.intrinsics.Params(),
                            got_before = first.ceres.intrinsics.Params();
      for (int i : slot) {
        const double std_px = r.ceres.intrinsics_std[i];
        std::printf(
            "  %s: error %+.4f std in the image, %+.4f std through the lens (std %.4f px)\n",
            ParamNames(c.truth.family)[i],
            (got_before[i] - want[i]) / first.ceres.intrinsics_std[i], (got[i] - want[i]) / std_px,
            std_px);
        EXPECT_NEAR(got[i], want[i], kWithinStd * std_px)
            << label << " " << ParamNames(c.truth.family)[i];
      }
      EXPECT_LT(r.ceres.rms_reproj_px, first.ceres.rms_reproj_px) << label;
      if (blur > 0 && c.model == LensModel::kPinholeEqui) {
        EXPECT_GT(std::abs(got_before[0] - want[0]),
                  kBiasedBeforeStd * first.ceres.intrinsics_std[0])
            << label;
      }
      EXPECT_NE(fit.log.find("through the lens, pass 1"), std::string::npos) << label;
    }
  }
}

}  // namespace
}  // namespace calibench
