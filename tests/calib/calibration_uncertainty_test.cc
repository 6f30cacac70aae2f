// calibrate's projection uncertainty (calib/calibration_uncertainty.h), its cross-validation
// (calib/cross_validate.h) and its page (calib/calibration_page.h) on synthetic views whose
// noise is known: independent corner noise, and an error every corner of a view shares.
#include "calib/calibration_uncertainty.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "calib/calibrate_camera.h"
#include "calib/calibration_page.h"
#include "calib/cross_validate.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

const CameraIntrinsics kTruth{520.0, 515.0, 90.0, 322.0, 236.0, -0.21, 0.08};

// 20 views with iid noise; per_view_affine: each view's pixels also move by A_v (pixel - centre),
// A_v ~ N(0, s^2) per entry, an error its corners share (tests/batch/jackknife_test.cc's model).
PointData Views(uint64_t seed, double per_view_affine) {
  Rng rng(seed);
  SyntheticBoardOptions board;
  board.num_views = 20;
  board.pixel_sigma_px = 0.2;
  SyntheticBoardViews synthetic = MakeBoardViews(kTruth, board, &rng);
  for (View& view : synthetic.views) {
    Eigen::Matrix2d a;
    a << rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal();
    const Eigen::Vector2d centre(kTruth.u0_px, kTruth.v0_px);
    for (Eigen::Vector2d& p : view.pixels) p += per_view_affine * a * (p - centre);
  }
  PointData data;
  data.views = synthetic.views;
  data.image_width = 640, data.image_height = 480;
  return data;
}

CalibrateOptions PinholeK2() {
  CalibrateOptions options;
  options.model = LensModel::kPinholeK2;
  options.jackknife = CalibrateOptions::Jackknife::kOn;
  return options;
}

TEST(CalibrationUncertainty, IndependentNoiseKeepsTheFormalFigure) {
  const CalibrateResult result = CalibratePoints(Views(31, 0.0), PinholeK2());
  ASSERT_TRUE(result.IsUsable()) << result.message;
  ASSERT_TRUE(result.calibration.uncertainty);
  const CalibrationUncertainty& u = *result.calibration.uncertainty;
  ASSERT_TRUE(u.jackknife);
  // Under iid noise the jackknife's spread matches the formal one; it overestimates by ~1.1-1.2x
  // at 20 views (tests/batch/jackknife_test.cc) and its own std error is ~sqrt(1 / (2 * 19)) = 16
  // %.
  EXPECT_GT(u.jackknife_ratio, 0.7);
  EXPECT_LT(u.jackknife_ratio, 1.6);
  // Held-out views: their error is what the formal figure predicts, noise and calibration part
  // (the excess over the noise is a small difference of large sums: measured 0.86 with this seed;
  // a calibration part off by 2x fails).
  EXPECT_NEAR(u.held_out_formal_ratio, 1.0, 0.1);
  EXPECT_GT(u.held_out_excess_ratio, 0.5);
  EXPECT_LT(u.held_out_excess_ratio, 1.6);
  // The quoted map is the formal one times the scale, and the camera file carries it.
  EXPECT_NEAR(u.quoted_map.median_px, u.scale * u.formal.median_px, 1e-12);
  EXPECT_TRUE(result.calibration.camera.projection.IsSet());
  EXPECT_EQ(result.calibration.camera.projection_scale, u.scale);
  // Smallest where the corners are: the centre below the median below the worst.
  EXPECT_LT(u.quoted_map.centre_px, u.quoted_map.median_px);
  EXPECT_LT(u.quoted_map.median_px, u.quoted_map.max_px);
}

TEST(CalibrationUncertainty, ErrorsSharedByAViewAreCaughtByTheJackknifeAndQuoted) {
  // 0.002 per entry moves a corner 300 px from the centre by ~0.6 px, shared by the view: the
  // formal figure (from the residuals, independent) cannot see it.
  const CalibrateResult result = CalibratePoints(Views(32, 0.002), PinholeK2());
  ASSERT_TRUE(result.IsUsable()) << result.message;
  const CalibrationUncertainty& u = *result.calibration.uncertainty;
  ASSERT_TRUE(u.jackknife);
  EXPECT_GT(u.jackknife_ratio, 1.5);
  EXPECT_DOUBLE_EQ(u.scale, u.jackknife_ratio);
  // The held-out views see it too: their excess over the noise is several times the formal
  // calibration part (measured 5.7 with this seed, the jackknife 3.3).
  EXPECT_GT(u.held_out_excess_ratio, 2.0);
  const std::string text = FormatProjectionUncertainty(u);
  EXPECT_NE(text.find("scaled by the jackknife"), std::string::npos) << text;
}

TEST(CrossValidation, HalvesOfIndependentViewsAgreeAndAShiftedHalfDoesNot) {
  const PointData data = Views(33, 0.0);
  const CalibrateResult result = CalibratePoints(data, PinholeK2());
  ASSERT_TRUE(result.IsUsable());
  const CrossValidation cv = CrossValidate(result, PinholeK2());
  ASSERT_TRUE(cv.ok) << cv.message;
  EXPECT_EQ(cv.half_views[0] + cv.half_views[1], 20);
  EXPECT_EQ(cv.comparison.verdict, CameraComparison::Verdict::kAgree) << FormatCrossValidation(cv);
  // The odd views seen through a lens with 2 % more focal length: their half is another camera.
  PointData changed = data;
  for (size_t v = 1; v < changed.views.size(); v += 2) {
    for (Eigen::Vector2d& p : changed.views[v].pixels) {
      p = Eigen::Vector2d(kTruth.u0_px, kTruth.v0_px) +
          1.02 * (p - Eigen::Vector2d(kTruth.u0_px, kTruth.v0_px));
    }
  }
  const CalibrateResult mixed = CalibratePoints(changed, PinholeK2());
  ASSERT_TRUE(mixed.IsUsable());
  const CrossValidation bad = CrossValidate(mixed, PinholeK2());
  ASSERT_TRUE(bad.ok) << bad.message;
  EXPECT_EQ(bad.comparison.verdict, CameraComparison::Verdict::kDiffer)
      << FormatCrossValidation(bad);
}

TEST(CrossValidation, TooFewViewsIsSaid) {
  PointData data = Views(34, 0.0);
  data.views.resize(5);
  const CalibrateResult result = CalibratePoints(data, PinholeK2());
  ASSERT_TRUE(result.IsUsable());
  const CrossValidation cv = CrossValidate(result, PinholeK2());
  EXPECT_FALSE(cv.ok);
  EXPECT_NE(cv.message.find("needs at least 6"), std::string::npos) << cv.message;
}

TEST(CalibrationPage, WritesTheMarkdownAndEveryFigureBesideTheCamera) {
  const CalibrateResult result = CalibratePoints(Views(35, 0.0), PinholeK2());
  ASSERT_TRUE(result.IsUsable());
  const CrossValidation cv = CrossValidate(result, PinholeK2());
  const std::string dir = ::testing::TempDir() + "/page";
  std::filesystem::create_directories(dir);
  CalibrationPageFiles files;
  std::string why;
  ASSERT_TRUE(WriteCalibrationPage(dir + "/cam.yaml", result, &cv, &files, &why)) << why;
  EXPECT_EQ(files.markdown, dir + "/cam.md");
  ASSERT_EQ(files.figures.size(), 5u);
  std::ifstream in(files.markdown);
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* figure : {"cam-uncertainty.png", "cam-residuals.png", "cam-view-residuals.png",
                             "cam-coverage.png", "cam-cross-validation.png"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + figure)) << figure;
    EXPECT_NE(md.find(std::string("(") + figure + ")"), std::string::npos) << figure;
  }
  // The numbers the page quotes are the result's.
  char median[32];
  std::snprintf(median, sizeof(median), "median %.3f px",
                result.calibration.uncertainty->quoted_map.median_px);
  EXPECT_NE(md.find(median), std::string::npos) << md;
  // An unwritable folder fails naming the file.
  EXPECT_FALSE(WriteCalibrationPage("/nonexistent/dir/cam.yaml", result, nullptr, &files, &why));
  EXPECT_NE(why.find("/nonexistent/dir/cam-"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
