#include "sim/measurements.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

SceneTruth ThesisCamera1Scene(CalibrationCase c) {
  SceneTruth scene;
  scene.calibration_case = c;
  scene.intrinsics = {822, 813, 87, 321, 239};
  scene.parent_from_cam.rotation << -1, 0, 0, 0, 0, 1, 0, 1, 0;
  scene.parent_from_cam.translation = {0.4, -2.3, 0.47};
  scene.points = ThesisFeaturePoints(10);
  scene.motion = Motion(ThesisMotionPreset(ThesisMotion::kSmall, c), {});
  return scene;
}

TEST(OracleSource, ContinuousMeasurementsAreExactProjections) {
  const SceneTruth scene = ThesisCamera1Scene(CalibrationCase::kMovingCamera);
  std::string why;
  const auto source = OracleSource::Create(scene, {}, 1, &why);
  ASSERT_NE(source, nullptr) << why;
  EXPECT_EQ(source->Breakpoints(), (std::vector<double>{0.0, 240.0}));
  EXPECT_EQ(source->NumFrames(), 2400);  // 10 Hz evaluation grid.
  Frame frame;
  source->Measure(12.345, 0, &frame);
  const Eigen::Matrix<double, 3, 4> m =
      scene.intrinsics.Matrix() * scene.CamFromParent().Matrix3x4();
  for (int i = 0; i < 10; ++i) {
    EXPECT_LT((frame.points_in_parent[i] - scene.PointInParent(i, 12.345)).norm(), 1e-12);
    const Eigen::Vector2d expected = (m * frame.points_in_parent[i].homogeneous()).hnormalized();
    EXPECT_LT((frame.pixels[i] - expected).norm(), 1e-9);
  }
}

TEST(OracleSource, SampledSourceHoldsEachFrameUntilTheNext) {
  OracleOptions options;
  options.sample_rate_hz = 30;
  const auto source =
      OracleSource::Create(ThesisCamera1Scene(CalibrationCase::kFixedCamera), options, 1, nullptr);
  ASSERT_NE(source, nullptr);
  ASSERT_EQ(source->NumFrames(), 7200);
  const std::vector<double>& b = source->Breakpoints();
  ASSERT_EQ(b.size(), 7201u);
  Frame start, end;
  source->Measure(b[5], 5, &start);
  source->Measure(b[6], 5, &end);  // End of segment 5: still frame 5.
  EXPECT_EQ(start.pixels, end.pixels);
  EXPECT_DOUBLE_EQ(end.time_s, 5.0 / 30);
  source->Measure(b[6], 6, &end);
  EXPECT_NE(start.pixels, end.pixels);
}

TEST(OracleSource, NoiseIsDeterministicPerSeedAndHasTheRequestedSpread) {
  OracleOptions options;
  options.noise.point_sigma_m = 0.1;
  options.noise.pixel_sigma_px = 0.5;
  const SceneTruth scene = ThesisCamera1Scene(CalibrationCase::kMovingCamera);
  const auto clean = OracleSource::Create(scene, {}, 42, nullptr);
  const auto a = OracleSource::Create(scene, options, 42, nullptr);
  const auto b = OracleSource::Create(scene, options, 42, nullptr);
  const auto c = OracleSource::Create(scene, options, 43, nullptr);
  ASSERT_TRUE(clean && a && b && c);
  EXPECT_EQ(a->Breakpoints().size(), 2401u);  // One draw per 0.1 s hold.
  double sum_sq_pixel = 0, sum_sq_point = 0;
  long n = 0;
  Frame fa, fb, fc, f0;
  for (int s = 0; s < 2400; ++s) {
    const double t = a->Breakpoints()[s] + 0.05;
    a->Measure(t, s, &fa);
    b->Measure(t, s, &fb);
    c->Measure(t, s, &fc);
    clean->Measure(t, 0, &f0);
    EXPECT_EQ(fa.pixels, fb.pixels);
    EXPECT_NE(fa.pixels, fc.pixels);
    for (int i = 0; i < 10; ++i) {
      sum_sq_pixel += (fa.pixels[i] - f0.pixels[i]).squaredNorm() / 2;
      sum_sq_point += (fa.points_in_parent[i] - f0.points_in_parent[i]).squaredNorm() / 3;
      ++n;
    }
  }
  // 24000 draws: the sample std has a relative standard error of 1/sqrt(2 * 48000) < 0.5%;
  // 2% is four standard errors.
  EXPECT_NEAR(std::sqrt(sum_sq_pixel / n), 0.5, 0.5 * 0.02);
  EXPECT_NEAR(std::sqrt(sum_sq_point / n), 0.1, 0.1 * 0.02);
}

// Gross outliers: a fraction of the measurements displaced by a wide Gaussian, on top of the
// pixel noise, which they leave draw for draw as it was.
TEST(OracleSource, OutliersAreTheRequestedFractionAndSpreadAndLeaveTheNoiseAlone) {
  OracleOptions noisy;
  noisy.noise.pixel_sigma_px = 0.5;
  OracleOptions contaminated = noisy;
  contaminated.noise.outlier_fraction = 0.2;
  contaminated.noise.outlier_sigma_px = 30.0;
  const SceneTruth scene = ThesisCamera1Scene(CalibrationCase::kMovingCamera);
  const auto with = OracleSource::Create(scene, contaminated, 42, nullptr);
  const auto without = OracleSource::Create(scene, noisy, 42, nullptr);
  ASSERT_TRUE(with && without);
  long outliers = 0, n = 0;
  double sum_sq_outlier = 0;
  Frame fw, fo;
  for (int s = 0; s < 2400; ++s) {
    const double t = with->Breakpoints()[s] + 0.05;
    with->Measure(t, s, &fw);
    without->Measure(t, s, &fo);
    for (int i = 0; i < 10; ++i, ++n) {
      const Eigen::Vector2d extra = fw.pixels[i] - fo.pixels[i];
      if (extra.squaredNorm() == 0) continue;  // The same noise draw, bit for bit.
      ++outliers;
      sum_sq_outlier += extra.squaredNorm() / 2;
    }
  }
  // 24000 measurements: the outlier count is binomial, std sqrt(24000 * 0.2 * 0.8) = 62 (0.26% of
  // the fraction); 0.01 is four of them. ~4800 outliers: the std of their displacement has a
  // relative standard error of 1/sqrt(2 * 9600) = 0.7%; 3% is four of them.
  EXPECT_NEAR(static_cast<double>(outliers) / n, 0.2, 0.01);
  EXPECT_NEAR(std::sqrt(sum_sq_outlier / outliers), 30.0, 30.0 * 0.03);

  std::string why;
  contaminated.noise.outlier_fraction = 1.5;
  EXPECT_EQ(OracleSource::Create(scene, contaminated, 1, &why), nullptr);
  EXPECT_NE(why.find("outlier_fraction must lie in [0, 1], got 1.5"), std::string::npos) << why;
}

TEST(OracleSource, RefusesPointsBehindTheCameraAndSaysWhich) {
  SceneTruth scene = ThesisCamera1Scene(CalibrationCase::kMovingCamera);
  scene.points.push_back({0, -30, 0});  // Behind camera 1 (its optical axis is +y).
  std::string why;
  EXPECT_EQ(OracleSource::Create(scene, {}, 1, &why), nullptr);
  EXPECT_NE(why.find("feature point 10"), std::string::npos) << why;
  EXPECT_NE(why.find("behind the camera"), std::string::npos) << why;
}

TEST(OracleSource, RefusesInvalidOptions) {
  OracleOptions options;
  options.noise.pixel_sigma_px = -1;
  std::string why;
  EXPECT_EQ(
      OracleSource::Create(ThesisCamera1Scene(CalibrationCase::kMovingCamera), options, 1, &why),
      nullptr);
  EXPECT_NE(why.find("pixel_sigma_px"), std::string::npos);
}

TEST(Random, TrialSeedsAreDistinctAndDrawsReproducible) {
  EXPECT_NE(TrialSeed(1, 0), TrialSeed(1, 1));
  EXPECT_NE(TrialSeed(1, 0), TrialSeed(2, 0));
  Rng a(TrialSeed(5, 3), RngStream::kPixelNoise), b(TrialSeed(5, 3), RngStream::kPixelNoise);
  Rng c(TrialSeed(5, 3), RngStream::kPointNoise);
  double sum = 0, sum_sq = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = a.Normal();
    EXPECT_EQ(x, b.Normal());
    sum += x;
    sum_sq += x * x;
  }
  EXPECT_NE(a.Normal(), c.Normal());
  // Mean: standard error 1/sqrt(n) = 0.0022; variance: sqrt(2/n) = 0.0032. Four of each.
  EXPECT_NEAR(sum / n, 0.0, 0.009);
  EXPECT_NEAR(sum_sq / n, 1.0, 0.013);
}

}  // namespace
}  // namespace calibench
