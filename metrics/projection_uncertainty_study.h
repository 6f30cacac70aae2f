// Monte Carlo validation of the projection uncertainty (batch/projection_uncertainty.h), as
// mrcal's test-projection-uncertainty does: one set of views (fixed geometry), re-solved with new
// pixel noise `draws` times; at each sample of a grid over the image, the world point that the
// truth sees there (at `distance_m`, or a ray) is taken into each view's board frame with the true
// poses, brought back with each re-solve's poses (averaged over the views) and projected through
// its intrinsics: the spread of those pixels (the worst-direction std of their 2 x 2 sample
// covariance) is the observed uncertainty; the prediction is the formula's at the truth with the
// true noise sigma (and, per draw, from the re-solve itself with sigma_hat: reported as the median
// over draws).
// The re-solved projection is batch/projection_uncertainty.h's ReprojectThroughEstimate.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "batch/projection_uncertainty.h"
#include "batch/refine.h"
#include "camera/view.h"

namespace calibench {

struct UncertaintyStudyOptions {
  LensModel model = LensModel::kPinholeK2;  // What each re-solve estimates (no skew).
  double pixel_sigma_px = 0.3;              // Noise on u and v of every corner, each draw.
  int draws = 100;  // Re-solves; the std of a std from n draws is ~1 / sqrt(2 n) (7 % at 100).
  double distance_m = std::numeric_limits<double>::infinity();  // Target units; infinity: rays.
  int grid_cols = 12;  // Samples across the image (rows by the aspect ratio).
  // Grid samples farther than this from every observed corner (px) are left out of the summary:
  // far outside the data the linearisation is not what is being validated. 0: keep all.
  double max_distance_to_data_px = 0.0;
  uint64_t seed = 1;  // Draw d's noise: Rng(seed + d, kPixelNoise).
  // One pose for every view (the views' points in one parent frame: a scenario's fixed camera,
  // RefineOptions::shared_pose); cam_from_board then holds that one pose.
  bool shared_pose = false;
  bool Check(std::string* why) const;
};

struct UncertaintyStudySample {
  Eigen::Vector2d pixel;
  double predicted_px = 0.0;        // At the truth, true sigma.
  double predicted_draws_px = 0.0;  // Median over the draws' own predictions (sigma_hat).
  double observed_px = 0.0;         // Worst-direction std of the re-solved projections.
};

struct UncertaintyStudyResult {
  bool ok = false;
  std::string message;                          // Why not ok.
  int draws_used = 0;                           // Re-solves that converged.
  std::vector<UncertaintyStudySample> samples;  // Grid samples inside the data's reach.
  // Over the samples: observed / predicted.
  double median_ratio = std::numeric_limits<double>::quiet_NaN();
  double p10_ratio = std::numeric_limits<double>::quiet_NaN();
  double p90_ratio = std::numeric_limits<double>::quiet_NaN();
  double median_predicted_px = std::numeric_limits<double>::quiet_NaN();
  double median_observed_px = std::numeric_limits<double>::quiet_NaN();
  double median_draw_ratio = std::numeric_limits<double>::quiet_NaN();  // Observed / draws' own.
};

// `views` hold noise-free pixels of `truth` seen at `cam_from_board` (e.g. sim/synthetic.h's
// MakeBoardViews or MakeWideBoardViews with pixel_sigma_px = 0), one pose per view or, with
// options.shared_pose, one for all.
// `measured_draws` (optional): each draw's views as a detector measured them in rendered images
// (view v of a draw seen from cam_from_board[v]; any subset of its points), in place of the
// Gaussian draws: their number (at least 10) replaces options.draws. The prediction stays the
// formula's at the truth on `views` with options.pixel_sigma_px, which the caller sets to the
// detector's measured error per axis: the study then asks whether an error that is not iid Gaussian
// (bias, correlation along an edge, a pixel grid) spreads the calibration as that sigma predicts.
UncertaintyStudyResult RunUncertaintyStudy(
    const CameraIntrinsics& truth, const std::vector<View>& views,
    const std::vector<Rigid3>& cam_from_board, int image_width, int image_height,
    const UncertaintyStudyOptions& options,
    const std::vector<std::vector<View>>* measured_draws = nullptr);

}  // namespace calibench
