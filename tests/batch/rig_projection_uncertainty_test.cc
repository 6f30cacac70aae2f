// Each rig camera's projection uncertainty (batch/rig_refine.h, RigRefineResult::projection)
// against the spread of its projection over Monte Carlo re-solves of the rig, as the single
// camera's (tests/metrics/projection_uncertainty_study_test.cc): the averaged frame of camera c
// is that of the frames it saw, each cam_from_board = cam_from_rig_c * rig_from_board_f.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "batch/projection_uncertainty.h"
#include "batch/rig_refine.h"
#include "sim/example_rigs.h"
#include "sim/rig_frames.h"
#include "util/random.h"

namespace calibench {
namespace {

// mrcal's tolerance (20 %) on the median over the grid; 80 draws scatter a std by 8 %.
constexpr double kMedianRatioTol = 0.20;
constexpr int kDraws = 80;

std::vector<Rigid3> CameraPoses(const std::vector<RigFrame>& frames, const CameraRig& rig,
                                const std::vector<Rigid3>& rig_from_board, int c) {
  std::vector<Rigid3> poses;
  for (size_t f = 0; f < frames.size(); ++f) {
    if (!frames[f].views_by_camera[c].points.empty()) {
      poses.push_back(rig.cameras[c].cam_from_rig * rig_from_board[f]);
    }
  }
  return poses;
}

TEST(RigProjectionUncertainty, EachCameraMatchesItsMonteCarloSpread) {
  const CameraRig truth = ExampleStereoRig();
  RigFramesOptions o;
  o.num_frames = 12;
  Rng rng(77);
  const SyntheticRigFrames exact = MakeRigFrames(truth, o, &rng);
  ASSERT_EQ(exact.frames.size(), 12u);
  RigRefineOptions refine;
  for (const RigCamera& camera : truth.cameras) refine.models.push_back(camera.lens_model);
  constexpr double kSigmaPx = 0.3;
  std::string why;
  refine.known_pixel_sigma_px = kSigmaPx;
  const RigRefineResult predicted = RefineRig(exact.frames, truth, exact.rig_from_board, refine);
  ASSERT_TRUE(predicted.IsUsable()) << predicted.message;
  ASSERT_EQ(predicted.projection.size(), 2u);
  refine.known_pixel_sigma_px = 0;
  refine.compute_covariance = false;
  for (int c = 0; c < 2; ++c) {
    ASSERT_TRUE(predicted.projection[c].IsSet()) << c;
    const RigCamera& camera = truth.cameras[c];
    const std::vector<Rigid3> true_poses =
        CameraPoses(exact.frames, truth, exact.rig_from_board, c);
    // A 6 x 5 grid inside the corners' reach.
    std::vector<Eigen::Vector2d> pixels;
    for (int j = 1; j <= 5; ++j) {
      for (int i = 1; i <= 6; ++i) {
        pixels.emplace_back(camera.image_width * (0.15 + 0.7 * (i - 1) / 5.0),
                            camera.image_height * (0.15 + 0.7 * (j - 1) / 4.0));
      }
    }
    std::vector<std::vector<Eigen::Vector2d>> draws(pixels.size());
    for (int d = 0; d < kDraws; ++d) {
      Rng noise(1000 + d, RngStream::kPixelNoise);
      std::vector<RigFrame> noisy = exact.frames;
      for (RigFrame& frame : noisy) {
        for (View& view : frame.views_by_camera) {
          for (Eigen::Vector2d& p : view.pixels) {
            p += kSigmaPx * Eigen::Vector2d(noise.Normal(), noise.Normal());
          }
        }
      }
      const RigRefineResult solved = RefineRig(noisy, truth, exact.rig_from_board, refine);
      ASSERT_TRUE(solved.IsUsable()) << solved.message;
      const std::vector<Rigid3> poses = CameraPoses(noisy, solved.rig, solved.rig_from_board, c);
      for (size_t s = 0; s < pixels.size(); ++s) {
        Eigen::Vector2d q;
        ASSERT_TRUE(ReprojectThroughEstimate(camera.intrinsics, solved.rig.cameras[c].intrinsics,
                                             true_poses, poses, pixels[s],
                                             std::numeric_limits<double>::infinity(), &q));
        draws[s].push_back(q);
      }
    }
    std::vector<double> ratios;
    for (size_t s = 0; s < pixels.size(); ++s) {
      const double observed = WorstStdPx(SampleCovariancePx2(draws[s]));
      PixelUncertainty u;
      ASSERT_TRUE(ProjectionUncertaintyAt(camera.intrinsics, predicted.projection[c], pixels[s],
                                          std::numeric_limits<double>::infinity(), &u, &why))
          << why;
      ratios.push_back(observed / u.worst_std_px);
    }
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    EXPECT_NEAR(ratios[ratios.size() / 2], 1.0, kMedianRatioTol) << "camera " << c;
  }
}

}  // namespace
}  // namespace calibench
