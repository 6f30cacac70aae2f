// Each rig camera's projection uncertainty (batch/rig_refine.h, RigRefineResult::projection)
// against the spread of its projection over Monte Carlo re-solves of the rig, as the single
// camera's (tests/metrics/projection_uncertainty_study_test.cc): the averaged frame of camera c
// is that of the frames it saw, each cam_from_board = cam_from_rig_c * rig_from_board_f. And the
// relative pose in pixels (RigRefineResult::transfer) against the same re-solves.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <limits>

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

Rigid3 CamFromCamZero(const CameraRig& rig, int c) {
  return rig.cameras[c].cam_from_rig * rig.cameras[0].cam_from_rig.Inverse();
}

// The relative pose in pixels (RigRefineResult::transfer): where camera c sees what camera 0 sees
// at a pixel of a 12-column grid over camera 0's data, rays at infinity (the rotation alone) and
// points at 1 m (the baseline counts), through each re-solved rig against the prediction at the
// truth; the median over the pixels that land inside camera c's image (a camera with fewer than
// 10 such pixels is left out; at least one camera at both distances is checked).
void ExpectTransfersMatchTheirSpread(const CameraRig& truth, const std::vector<RigFrame>& frames,
                                     const RigRefineResult& predicted,
                                     const std::vector<RigRefineResult>& solves) {
  const RigCamera& zero = truth.cameras[0];
  const ImageGrid grid = ImageGrid::Over(zero.image_width, zero.image_height, 12);
  int checked = 0;
  for (int c = 1; c < truth.NumCameras(); ++c) {
    ASSERT_TRUE(predicted.transfer[c].IsSet()) << c;
    const RigCamera& camera = truth.cameras[c];
    for (const double distance_m : {std::numeric_limits<double>::infinity(), 1.0}) {
      std::vector<double> ratios;
      for (int j = 0; j < grid.rows; ++j) {
        for (int i = 0; i < grid.cols; ++i) {
          const Eigen::Vector2d pixel0 = grid.PixelAt(i, j);
          bool near = false;
          for (const RigFrame& frame : frames) {
            for (const Eigen::Vector2d& p : frame.views_by_camera[0].pixels) {
              near = near || (p - pixel0).norm() < 40;
            }
          }
          PixelUncertainty u;
          Eigen::Vector2d at;
          if (!near ||
              !TransferUncertaintyAt(zero.intrinsics, camera.intrinsics, CamFromCamZero(truth, c),
                                     predicted.transfer[c], pixel0, distance_m, &u, &at, nullptr) ||
              at.x() < 0 || at.y() < 0 || at.x() > camera.image_width - 1 ||
              at.y() > camera.image_height - 1) {
            continue;
          }
          std::vector<Eigen::Vector2d> draws;
          for (const RigRefineResult& solve : solves) {
            Eigen::Vector2d q;
            ASSERT_TRUE(TransferPixel(solve.rig.cameras[0].intrinsics,
                                      solve.rig.cameras[c].intrinsics, CamFromCamZero(solve.rig, c),
                                      pixel0, distance_m, &q));
            draws.push_back(q);
          }
          ratios.push_back(WorstStdPx(SampleCovariancePx2(draws)) / u.worst_std_px);
        }
      }
      if (ratios.size() < 10) continue;  // Camera c hardly sees what camera 0 sees.
      ++checked;
      std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
      std::printf("transfer into camera %d at %g m: observed / predicted %.3f over %zu pixels\n", c,
                  distance_m, ratios[ratios.size() / 2], ratios.size());
      EXPECT_NEAR(ratios[ratios.size() / 2], 1.0, kMedianRatioTol)
          << "transfer into camera " << c << " at " << distance_m << " m";
    }
  }
  EXPECT_GE(checked, 2) << "no camera sees enough of what camera 0 sees";
}

// For each camera of `truth`, rays at infinity and points at 0.6 m (the camera's translation in
// the rig counts there), against kDraws re-solves of `num_frames` frames.
void ExpectEachCameraMatchesItsSpread(const CameraRig& truth, int num_frames, bool whole_board) {
  RigFramesOptions o;
  o.num_frames = num_frames;
  o.whole_board = whole_board;
  Rng rng(77);
  const SyntheticRigFrames exact = MakeRigFrames(truth, o, &rng);
  ASSERT_EQ(static_cast<int>(exact.frames.size()), num_frames);
  RigRefineOptions refine;
  for (const RigCamera& camera : truth.cameras) refine.models.push_back(camera.lens_model);
  constexpr double kSigmaPx = 0.3;
  refine.known_pixel_sigma_px = kSigmaPx;
  const RigRefineResult predicted = RefineRig(exact.frames, truth, exact.rig_from_board, refine);
  ASSERT_TRUE(predicted.IsUsable()) << predicted.message;
  ASSERT_EQ(static_cast<int>(predicted.projection.size()), truth.NumCameras());
  refine.known_pixel_sigma_px = 0;
  refine.compute_covariance = false;
  std::vector<RigRefineResult> solves;
  std::vector<std::vector<RigFrame>> noisy_frames;
  for (int d = 0; d < kDraws; ++d) {
    Rng noise(1000 + d, RngStream::kPixelNoise);
    std::vector<RigFrame> noisy = exact.frames;
    for (RigFrame& frame : noisy) {
      for (View& view : frame.views_by_camera) {
        for (Eigen::Vector2d& p : view.pixels) {
          p += kSigmaPx * NormalPair<Eigen::Vector2d>(&noise);
        }
      }
    }
    solves.push_back(RefineRig(noisy, truth, exact.rig_from_board, refine));
    ASSERT_TRUE(solves.back().IsUsable()) << solves.back().message;
    noisy_frames.push_back(std::move(noisy));
  }
  ExpectTransfersMatchTheirSpread(truth, exact.frames, predicted, solves);
  for (int c = 0; c < truth.NumCameras(); ++c) {
    ASSERT_TRUE(predicted.projection[c].IsSet()) << c;
    const RigCamera& camera = truth.cameras[c];
    const std::vector<Rigid3> true_poses =
        CameraPoses(exact.frames, truth, exact.rig_from_board, c);
    // The pixels within 40 px of a corner the camera saw, on a 12-column grid.
    const ImageGrid grid = ImageGrid::Over(camera.image_width, camera.image_height, 12);
    std::vector<Eigen::Vector2d> pixels;
    for (int j = 0; j < grid.rows; ++j) {
      for (int i = 0; i < grid.cols; ++i) {
        bool near = false;
        for (const RigFrame& frame : exact.frames) {
          for (const Eigen::Vector2d& p : frame.views_by_camera[c].pixels) {
            near = near || (p - grid.PixelAt(i, j)).norm() < 40;
          }
        }
        if (near) pixels.push_back(grid.PixelAt(i, j));
      }
    }
    ASSERT_GE(pixels.size(), 10u) << "camera " << c;
    for (const double distance_m : {std::numeric_limits<double>::infinity(), 0.6}) {
      std::vector<double> ratios;
      for (const Eigen::Vector2d& pixel : pixels) {
        std::vector<Eigen::Vector2d> draws;
        for (int d = 0; d < kDraws; ++d) {
          const std::vector<Rigid3> poses =
              CameraPoses(noisy_frames[d], solves[d].rig, solves[d].rig_from_board, c);
          Eigen::Vector2d q;
          ASSERT_TRUE(ReprojectThroughEstimate(camera.intrinsics,
                                               solves[d].rig.cameras[c].intrinsics, true_poses,
                                               poses, pixel, distance_m, &q));
          draws.push_back(q);
        }
        PixelUncertainty u;
        std::string why;
        ASSERT_TRUE(ProjectionUncertaintyAt(camera.intrinsics, predicted.projection[c], pixel,
                                            distance_m, &u, &why))
            << why;
        ratios.push_back(WorstStdPx(SampleCovariancePx2(draws)) / u.worst_std_px);
      }
      std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
      EXPECT_NEAR(ratios[ratios.size() / 2], 1.0, kMedianRatioTol)
          << "camera " << c << " at " << distance_m << " m";
    }
  }
}

TEST(RigProjectionUncertainty, StereoCamerasMatchTheirMonteCarloSpread) {
  ExpectEachCameraMatchesItsSpread(ExampleStereoRig(), 12, true);
}

// Cameras turned by 45 and 90 degrees (a missing R_c or translation term shows), a double sphere
// among them, partial boards.
TEST(RigProjectionUncertainty, MixedThreeCameraRigMatchesItsMonteCarloSpread) {
  ExpectEachCameraMatchesItsSpread(ExampleMixedThreeCameraRig(), 16, false);
}

}  // namespace
}  // namespace calibench
