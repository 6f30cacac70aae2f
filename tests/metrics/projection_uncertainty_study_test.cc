// The projection uncertainty validated by Monte Carlo re-solves (metrics/projection_uncertainty_
// study.h): a narrow and a wide lens, rays and a near point. docs/results/uncertainty.md has the
// full table (calibench uncertainty-study).
#include "metrics/projection_uncertainty_study.h"

#include <gtest/gtest.h>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

// mrcal's own tolerance for its Monte Carlo check (test-projection-uncertainty.py): the predicted
// std within 20 % of the observed. With 100 draws the observed std itself scatters by
// 1 / sqrt(2 * 100) = 7 %, so a correct formula passes and a factor-2 slip (the quaternion
// tangent) or a missing frame term (2-5x at the image's edge) fails.
constexpr double kMedianRatioTol = 0.20;
// Single grid samples: 10th-90th percentile of observed / predicted within 35 % (the 7 %
// sampling scatter of each sample's std, at 1.3 sigma either side, plus the 20 %).
constexpr double kSampleRatioTol = 0.35;
constexpr int kDraws = 100;

void ExpectValidated(const UncertaintyStudyResult& r) {
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_GE(r.draws_used, kDraws - 2);
  EXPECT_NEAR(r.median_ratio, 1.0, kMedianRatioTol)
      << "observed " << r.median_observed_px << " px, predicted " << r.median_predicted_px;
  EXPECT_GT(r.p10_ratio, 1.0 - kSampleRatioTol);
  EXPECT_LT(r.p90_ratio, 1.0 + kSampleRatioTol);
  // Each draw's own prediction (sigma_hat from its residuals) tells the same.
  EXPECT_NEAR(r.median_draw_ratio, 1.0, kMedianRatioTol);
}

TEST(ProjectionUncertaintyStudy, PinholeRaysAndNearPointsMatchTheirMonteCarloSpread) {
  const CameraIntrinsics truth{520.0, 515.0, 90.0, 322.0, 236.0, -0.21, 0.08};
  SyntheticBoardOptions board;
  board.num_views = 12;
  Rng rng(21);
  const SyntheticBoardViews data = MakeBoardViews(truth, board, &rng);
  UncertaintyStudyOptions options;
  options.draws = kDraws;
  options.max_distance_to_data_px = 40;
  ExpectValidated(RunUncertaintyStudy(truth, data.views, data.cam_from_board, 640, 480, options));
  options.distance_m = 0.5;  // At the boards' distance: the eps terms count.
  ExpectValidated(RunUncertaintyStudy(truth, data.views, data.cam_from_board, 640, 480, options));
}

TEST(ProjectionUncertaintyStudy, WideDoubleSphereMatchesItsMonteCarloSpread) {
  CameraIntrinsics truth;
  truth.family = LensFamily::kDoubleSphere;
  truth.fku_px = 330, truth.fkv_px = 331, truth.u0_px = 511, truth.v0_px = 509;
  truth.xi = -0.2, truth.alpha = 0.6;
  WideBoardOptions board;
  board.num_views = 15;
  board.max_angle_deg = 80;
  Rng rng(22);
  const SyntheticBoardViews data = MakeWideBoardViews(truth, board, &rng);
  UncertaintyStudyOptions options;
  options.model = LensModel::kDoubleSphere;
  options.draws = kDraws;
  options.max_distance_to_data_px = 60;
  ExpectValidated(RunUncertaintyStudy(truth, data.views, data.cam_from_board, board.image_width,
                                      board.image_height, options));
}

TEST(ProjectionUncertaintyStudy, OneSharedPoseMatchesItsMonteCarloSpread) {
  // A scenario's fixed camera: 10 frames of 40 points each, spread in depth 1-3 m in front of it,
  // in one parent frame; one pose for all (the joint covariance of batch/refine.cc FillCovariance).
  const CameraIntrinsics truth{520.0, 515.0, 90.0, 322.0, 236.0, -0.21, 0.08};
  Rng rng(23);
  const Rigid3 cam_from_parent = RandomPose(0.5, &rng);
  std::vector<View> views(10);
  for (View& view : views) {
    while (view.points.size() < 40) {
      const double z = rng.Uniform(1, 3), y = rng.Uniform(-0.8, 0.8);  // Last first.
      const Eigen::Vector3d in_cam(rng.Uniform(-1, 1), y, z);
      Eigen::Vector2d pixel;
      if (!ProjectPoint(truth, in_cam, &pixel) || pixel.x() < 0 || pixel.y() < 0 ||
          pixel.x() > 639 || pixel.y() > 479) {
        continue;
      }
      view.points.push_back(cam_from_parent.Inverse() * in_cam);
      view.pixels.push_back(pixel);
    }
  }
  UncertaintyStudyOptions options;
  options.shared_pose = true;
  options.draws = kDraws;
  options.max_distance_to_data_px = 40;
  ExpectValidated(RunUncertaintyStudy(truth, views, {cam_from_parent}, 640, 480, options));
  options.distance_m = 2.0;
  ExpectValidated(RunUncertaintyStudy(truth, views, {cam_from_parent}, 640, 480, options));
}

TEST(ProjectionUncertaintyStudy, MeasuredDrawsSpreadAsTheirNoiseNotTheirFixedError) {
  // A detector's corners as the rendered study measures them: a fixed error per corner (the same
  // in every draw: the geometry on the pixel grid), 0.2 px, plus noise that changes, 0.1 px. The
  // re-solves spread as the 0.1 px predicts; each draw's own sigma_hat (from its residuals) holds
  // both, sqrt(0.1^2 + 0.2^2) = 2.2x the noise, so its ratio is ~0.45: below kOwnRatioMax.
  constexpr double kNoisePx = 0.1, kFixedPx = 0.2, kOwnRatioMax = 0.6;
  const CameraIntrinsics truth{520.0, 515.0, 90.0, 322.0, 236.0, -0.21, 0.08};
  SyntheticBoardOptions board;
  board.num_views = 12;
  Rng rng(24);
  const SyntheticBoardViews data = MakeBoardViews(truth, board, &rng);
  std::vector<View> fixed = data.views;
  for (View& view : fixed) {
    for (Eigen::Vector2d& p : view.pixels) p += kFixedPx * NormalPair<Eigen::Vector2d>(&rng);
  }
  std::vector<std::vector<View>> draws(kDraws, fixed);
  for (std::vector<View>& draw : draws) {
    for (View& view : draw) {
      for (Eigen::Vector2d& p : view.pixels) p += kNoisePx * NormalPair<Eigen::Vector2d>(&rng);
    }
  }
  UncertaintyStudyOptions options;
  options.pixel_sigma_px = kNoisePx;
  options.max_distance_to_data_px = 40;
  const UncertaintyStudyResult r =
      RunUncertaintyStudy(truth, data.views, data.cam_from_board, 640, 480, options, &draws);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_GE(r.draws_used, kDraws - 2);
  EXPECT_NEAR(r.median_ratio, 1.0, kMedianRatioTol)
      << "observed " << r.median_observed_px << " px, predicted " << r.median_predicted_px;
  EXPECT_LT(r.median_draw_ratio, kOwnRatioMax);
  // A draw whose view count is not the study's is refused, naming both counts.
  draws[3].pop_back();
  const UncertaintyStudyResult bad =
      RunUncertaintyStudy(truth, data.views, data.cam_from_board, 640, 480, options, &draws);
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.message.find("11 views where the study has 12"), std::string::npos) << bad.message;
  // Fewer than 10 measured draws are refused, whatever options.draws says.
  draws.resize(5);
  const UncertaintyStudyResult few =
      RunUncertaintyStudy(truth, data.views, data.cam_from_board, 640, 480, options, &draws);
  EXPECT_FALSE(few.ok);
  EXPECT_NE(few.message.find("fewer than 10 measured draws (5)"), std::string::npos) << few.message;
}

TEST(ProjectionUncertaintyStudy, BadOptionsAreRefusedWithAReason) {
  UncertaintyStudyOptions options;
  options.draws = 3;
  const UncertaintyStudyResult r = RunUncertaintyStudy({}, {View{}}, {Rigid3{}}, 640, 480, options);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("draws"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace calibench
