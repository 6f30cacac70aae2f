// Where in the image a calibration can be trusted: the projection uncertainty of a calibrated
// camera (batch/projection_uncertainty.h) as `calibrate` reports, writes and draws it.
//
// Two figures over a grid of the image (rays at infinity unless asked):
//   formal     sqrt of the worst eigenvalue of G Cov(z) G^T, Cov(z) from sigma_hat^2 (J^T J)^-1:
//              independent corner noise of the size of the residuals (mrcal's figure);
//   jackknife  the leave-one-view-out spread of the projection: refit i (without view i)
//              reprojects each grid pixel through the frame of the full fit's poses
//              (ReprojectThroughEstimate), var = (N - 1) / N sum_i (q_i - q_mean)(q_i - q_mean)^T,
//              worst direction. It needs no noise model and sees what the formal figure cannot:
//              corners of one view that share their errors (blur, board flatness, lens misfit).
// Quoted: the formal map scaled by s = max(1, median over the grid of jackknife / formal), the
// scale written beside it.
// Held-out views check it: view i's corners against refit i (the calibration without view i),
// its pose fitted with refit i's intrinsics fixed. Linearised, the residual after the pose fit is
// r = (I - H)(e + J_theta d_theta), H the projection onto the view's 6 pose columns, e the
// corners' noise, d_theta refit i's error (its covariance N / (N - 1) times the full fit's), so
//     E |r|^2 = sigma^2 (2n - 6) + C,  C = tr((I - H) J_theta Cov(theta) J_theta^T):
// the noise plus what of the calibration's uncertainty a pose cannot absorb. The noise dominates
// a single view's error, so the telling figure is the excess over it summed over the views,
// sqrt(sum (|r|^2 - sigma^2 (2n - 6)) / sum C): ~1 when the formal Cov(theta) is right, ~s when
// the quoted one is. The per-view ratios to sqrt(E |r|^2 / 2n) (formal C, and s^2 C) are printed
// beside it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "batch/jackknife.h"
#include "batch/projection_uncertainty.h"
#include "batch/refine.h"

namespace calibench {

struct CalibrationUncertaintyOptions {
  int grid_cols = 40;                                           // Samples across the image.
  double distance_m = std::numeric_limits<double>::infinity();  // Target units; infinity: rays.
};

struct CalibrationUncertainty {
  UncertaintyMap formal;
  std::optional<UncertaintyMap> jackknife;  // With a usable jackknife of the same fit.
  // Median over the grid of jackknife / formal (NaN without the jackknife).
  double jackknife_ratio = std::numeric_limits<double>::quiet_NaN();
  double scale = 1.0;           // max(1, jackknife_ratio): applied to the quoted figure.
  ProjectionCovariance quoted;  // The formal Cov(z) times scale^2.
  UncertaintyMap quoted_map;
  double distance_m = std::numeric_limits<double>::infinity();
  // Held-out views (with a jackknife): the median over views of their RMS error per coordinate
  // (px) and of its ratio to the formal and to the quoted prediction (header comment).
  int held_out_views = 0;
  double held_out_rms_px = std::numeric_limits<double>::quiet_NaN();
  double held_out_formal_ratio = std::numeric_limits<double>::quiet_NaN();
  double held_out_quoted_ratio = std::numeric_limits<double>::quiet_NaN();
  // sqrt(sum_i (|r_i|^2 - sigma^2 (2 n_i - 6)) / sum_i tr((I - H) J Cov J^T)): how many times the
  // formal calibration uncertainty the held-out errors in excess of the noise show (~1 when the
  // formal figure is right, ~scale when the quoted one is); 0 when the excess is negative.
  double held_out_excess_ratio = std::numeric_limits<double>::quiet_NaN();
};

// nullopt when `fit` carries no projection covariance (not computed, evaluate-only).
// `views` are those `fit` used and `jackknife` is that of `fit` (the same views, in order);
// `refine` the options `fit` was made with (the held-out poses are fitted with them).
std::optional<CalibrationUncertainty> AssessProjectionUncertainty(
    const std::vector<View>& views, const RefineOptions& refine, const RefineResult& fit,
    const std::optional<JackknifeResult>& jackknife, int image_width, int image_height,
    const CalibrationUncertaintyOptions& options);

// Two lines for the calibrate printout: the quoted figure (centre, median, worst and where) and,
// with a jackknife, how it compares with the formal one.
std::string FormatProjectionUncertainty(const CalibrationUncertainty& u);

}  // namespace calibench
