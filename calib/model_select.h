// calibrate --model auto: fit every candidate lens model to the same points, compare them on
// views they were not fitted to, and pick the simplest that predicts as well as the best.
//
// Candidates (kAutoCandidates): pinhole-radtan4, pinhole-radtan5, pinhole-equi, unified, eucm,
// double-sphere, each through CalibrateFromPoints (its own start: zhang, cv::fisheye or the wide
// start; then ceres). A candidate that cannot start or refine is listed with the reason, skipped.
//
// Held-out error (leave-k-views-out): view v goes to fold v mod K, K = min(folds, views). For
// each fold, ceres refits the intrinsics and poses on the other views (from the full fit), then,
// with those intrinsics fixed (RefineOptions::fix_intrinsics), fits each held-out view's pose
// alone; the held-out view's squared residuals at that pose are its held-out error e_v (a sum
// over its points). cv_rms_px = sqrt(sum_v e_v / (held-out points)).
//
// The rule (stated in the output too):
//   Only the candidates that use the most views are compared (pinhole-equi leaves out views with
//   rays past 90 degrees: its held-out error over fewer, easier views would not be comparable).
//   best = the compared candidate with the least cv_rms_px. A compared candidate is within noise
//   of the best when the paired difference of held-out errors over the views,
//   d_v = e_v(candidate) - e_v(best), is not significantly positive:
//       z = mean(d) / (std(d) / sqrt(n)) <= kWithinNoiseZ (= 2; z = 0 when every d_v is 0),
//   and its held-out RMS is within the RMS's own noise of the best's:
//       cv_rms_px <= best cv_rms_px (1 + kRmsNoiseSigmas / sqrt(2 m)),
//   m the held-out residuals (2 per point): an RMS of m Gaussian residuals has a relative
//   standard deviation of 1 / sqrt(2 m), and 3 of them is not noise.
//   Pick the candidate with the fewest free parameters among those within noise (the best is),
//   ties broken by the candidates' order above.
// Pairing per view removes what the models share (the view's corner noise and pose); a view, not
// a point, is the unit because a view's residuals share its pose error. The RMS test guards the
// paired test where the views' differences scatter widely: a pinhole radtan on a 160-degree lens,
// 25 times the best's held-out RMS, has z = 2.9 only.
//
// Projection difference against the best (proj_diff_*_px): pixels on a grid (kDiffGridStep px)
// inside the image and within the farthest observed corner's radius from the best model's
// principal point, lifted through the best model to rays and projected through the candidate:
// RMS and largest distance. Both cameras sit in their own fitted frame (no rotation is fitted
// between them), so the figure also holds the small rotation the poses absorb.
#pragma once

#include <string>
#include <vector>

#include "calib/calibrate.h"

namespace calibench {

const std::vector<LensModel>& AutoCandidates();
constexpr double kWithinNoiseZ = 2.0;
constexpr double kRmsNoiseSigmas = 3.0;
constexpr int kDiffGridStep = 16;

struct ModelSelectOptions {
  std::vector<LensModel> candidates = AutoCandidates();
  int folds = 5;  // K of leave-k-views-out (held-out views per fold ~ views / K).
  bool estimate_skew = false;
  bool Check(std::string* why) const;
};

struct ModelScore {
  CalibrateReport report;        // The full fit.
  std::string note;              // Why not fitted, or what the start said.
  std::vector<int> used_views;   // Indices into the data's views.
  std::vector<double> held_out;  // e_v per used view [px^2], same order.
  double rms_px = 0, cv_rms_px = 0;
  double z_vs_best = 0;  // The rule's z (0 for the best).
  double proj_diff_rms_px = 0, proj_diff_max_px = 0;
  long held_out_points = 0;
  LensModel model = LensModel::kPinholeK2;
  int free_params = 0;
  int views = 0;        // Views the fit used.
  bool fitted = false;  // Started and refined.
  bool cross_validated = false;
  bool comparable = false;  // Cross-validated on the most views any candidate uses.
  bool within_noise = false;
};

struct ModelSelection {
  std::vector<ModelScore> scores;  // One per candidate, in the candidates' order.
  int best = -1;                   // Least cv_rms_px.
  int chosen = -1;                 // The rule's pick.
  std::string reason;              // Why, in one sentence.
  bool IsUsable() const { return chosen >= 0; }
};

// Fits and compares the candidates on `data` (no --init: each from scratch).
ModelSelection SelectLensModel(const PointData& data, const ModelSelectOptions& options);

// The table, the rule and the pick with its reason.
std::string FormatModelSelection(const ModelSelection& selection);

}  // namespace calibench
