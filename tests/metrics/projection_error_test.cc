// proj_err_px and proj_err_ratio (metrics/metrics.h ProjectionErrorAgainst): zero for the truth
// itself, NaN ratio without a covariance or with free distortion terms and no Cov(z) of its own,
// and over Monte Carlo draws of oracle noise the ratio of ceres (pinhole and pinhole-k2) and of the
// EKF (their covariance's prediction) has RMS ~1.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "methods/options.h"
#include "metrics/metrics.h"
#include "sim/synthetic.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

constexpr int kWidth = 640, kHeight = 480;  // SyntheticTrial's image.

CameraEstimate EstimateOf(const CameraSpec& camera) {
  CameraEstimate e;
  e.has_camera = true;
  e.intrinsics = camera.intrinsics;
  e.parent_from_cam = camera.ParentFromCam();
  e.cam_from_parent = e.parent_from_cam.Inverse();
  return e;
}

TEST(ProjectionError, ZeroForTheTruthAndNoRatioWithoutACompleteCovariance) {
  const CameraSpec truth = SwayingBoardRig().scene.CameraAt(0);
  CameraEstimate e = EstimateOf(truth);
  const ProjectionError exact = ProjectionErrorAgainst(e, truth, kWidth, kHeight, {});
  EXPECT_EQ(exact.pixels, 16 * 12);      // Every pixel of the pinhole's grid.
  EXPECT_LT(exact.rms_px, 1e-9);         // Unproject, project: rounding only.
  EXPECT_TRUE(std::isnan(exact.ratio));  // No covariance.
  // A 1 px shift of the principal point moves every pixel by 1 px.
  e.intrinsics.u0_px += 1.0;
  constexpr double kLinearTolPx = 1e-9;
  EXPECT_NEAR(ProjectionErrorAgainst(e, truth, kWidth, kHeight, {}).rms_px, 1.0, kLinearTolPx);
  // With a covariance of the shift's size in u0 alone, the prediction is 1 px everywhere.
  e.covariance =
      Eigen::MatrixXd::Zero(CameraEstimate::kCovarianceSize, CameraEstimate::kCovarianceSize);
  e.covariance(3, 3) = 1.0;
  EXPECT_NEAR(ProjectionErrorAgainst(e, truth, kWidth, kHeight, {}).ratio, 1.0, kLinearTolPx);
  // With v0 as uncertain, the predicted error is sqrt(1 + 1) px (the trace, not the worst
  // direction's 1 px): the same 1 px error is 1 / sqrt(2) of it.
  e.covariance(4, 4) = 1.0;
  const ProjectionError both = ProjectionErrorAgainst(e, truth, kWidth, kHeight, {});
  EXPECT_NEAR(both.predicted_px, std::sqrt(2.0), kLinearTolPx);
  EXPECT_NEAR(both.ratio, 1.0 / std::sqrt(2.0), kLinearTolPx);
  // A lens model with free distortion: the 11 x 11 lacks its terms, no ratio, unless the estimate
  // carries its own Cov(z) (here the same 1 px in u0 and v0: the same ratio).
  e.lens = LensModel::kPinholeK2;
  EXPECT_TRUE(std::isnan(ProjectionErrorAgainst(e, truth, kWidth, kHeight, {}).ratio));
  e.projection.covariance(3, 3) = e.projection.covariance(4, 4) = 1.0;
  e.projection.num_views = 1;
  EXPECT_NEAR(ProjectionErrorAgainst(e, truth, kWidth, kHeight, {}).ratio, 1.0 / std::sqrt(2.0),
              kLinearTolPx);
  // No camera, or no image: nothing.
  EXPECT_TRUE(
      std::isnan(ProjectionErrorAgainst(CameraEstimate{}, truth, kWidth, kHeight, {}).rms_px));
  EXPECT_TRUE(std::isnan(ProjectionErrorAgainst(e, truth, 0, 0, {}).rms_px));
}

// The RMS over draws of proj_err_ratio of `type` on the swaying two-board rig (oracle frames at
// 10 frames/s, white noise of sigma_px, duration_s), each draw its own noise seed.
double RmsRatio(const std::string& type, int draws, double duration_s, double sigma_px,
                const std::string& model = "") {
  const BoardRigScene rig = SwayingBoardRig();
  SceneTruth scene = rig.scene;
  scene.duration_s = duration_s;
  OracleOptions frames;
  frames.sample_rate_hz = 10;
  frames.noise.pixel_sigma_px = sigma_px;
  const CameraSpec truth = scene.CameraAt(0);  // A static mount.
  double sum_sq = 0;
  int n = 0;
  for (int draw = 0; draw < draws; ++draw) {
    auto trial = SyntheticTrial::Create(scene, frames, 100 + draw, rig.layouts);
    if (trial == nullptr) return NAN;
    const std::unique_ptr<Method> method = MakeMethod(type);
    std::string why;
    if (!model.empty()) {
      EXPECT_TRUE(SetOption(method.get(), "model", model, &why)) << why;
    }
    if (type == "ekf") {  // Its noise model as simulated (ceres estimates sigma from residuals).
      EXPECT_TRUE(SetOption(method.get(), "pixel_sigma_px", std::to_string(sigma_px), &why)) << why;
    }
    const MethodResult r = method->Run(trial->input, nullptr);
    EXPECT_TRUE(r.IsUsable()) << type << ": " << r.message;
    if (!r.IsUsable()) continue;
    const ProjectionError p = ProjectionErrorAgainst(r.estimate, truth, kWidth, kHeight, {});
    EXPECT_TRUE(std::isfinite(p.ratio)) << type;
    sum_sq += p.ratio * p.ratio;
    ++n;
  }
  return n ? std::sqrt(sum_sq / n) : NAN;
}

// ceres (sigma from its residuals) and the EKF (its noise model as simulated, 0.3 px) on 6 s of
// the swaying rig at 10 frames/s, 30 noise draws: a consistent covariance puts the RMS ratio at 1
// up to the first-order prediction and the draws' spread. The error over the image is dominated by
// about one direction of the parameters (ratio^2 has the spread of chi^2 with 1.4 degrees of
// freedom over 300 draws: mean 0.96 and 0.94, std 1.15 and 1.11), so the RMS of 30 draws has a
// std of ~0.11; kTol = 0.35 is 3.3 of it. Measured: ceres 0.830, ekf 0.898, ceres pinhole-k2
// 0.881 (seeds 100-129; over 300 draws ceres and ekf 0.979 and 0.968). A covariance off by a factor
// 2 in std, a wrong rotation block or a missing sigma^2 fails; the worst-direction std in place of
// sqrt(trace) (a factor in [1, sqrt 2]) would not be caught by this test alone (the first test pins
// the formula).
TEST(ProjectionError, CeresAndEkfRatiosHaveRmsNearOneOverDraws) {
  constexpr int kDraws = 30;
  constexpr double kSigmaPx = 0.3, kDurationS = 6.0, kTol = 0.35;
  const double ceres = RmsRatio("ceres", kDraws, kDurationS, kSigmaPx);
  const double ekf = RmsRatio("ekf", kDraws, kDurationS, kSigmaPx);
  // ceres fitting k1, k2 too (its own Cov(z) with the lens terms, RefineResult::projection).
  const double ceres_k2 = RmsRatio("ceres", kDraws, kDurationS, kSigmaPx, "pinhole-k2");
  std::printf("RMS proj_err_ratio over %d draws: ceres %.3f, ekf %.3f, ceres pinhole-k2 %.3f\n",
              kDraws, ceres, ekf, ceres_k2);
  EXPECT_NEAR(ceres, 1.0, kTol);
  EXPECT_NEAR(ekf, 1.0, kTol);
  EXPECT_NEAR(ceres_k2, 1.0, kTol);
}

}  // namespace
}  // namespace calibench
