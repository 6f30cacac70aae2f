// Monte Carlo validation of the projection uncertainty (metrics/projection_uncertainty_study.h).
#include "metrics/projection_uncertainty_study.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "util/random.h"

namespace calibench {
namespace {

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(at));
  const size_t hi = std::min(values.size() - 1, lo + 1);
  return values[lo] + (at - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

RefineOptions StudyRefineOptions(const UncertaintyStudyOptions& options) {
  RefineOptions refine;
  refine.model = options.model;
  refine.estimate_skew = false;
  refine.shared_pose = options.shared_pose;
  refine.compute_pose_covariance = options.shared_pose;  // Cov(z) of a shared pose needs it.
  return refine;
}

}  // namespace

bool UncertaintyStudyOptions::Check(std::string* why) const {
  std::string problem;
  if (!(pixel_sigma_px > 0)) problem = "pixel_sigma_px must be positive";
  if (draws < 10) problem = "draws must be at least 10";
  if (!(distance_m > 0)) problem = "distance_m must be positive (or infinity)";
  if (grid_cols < 2) problem = "grid_cols must be at least 2";
  if (!(max_distance_to_data_px >= 0)) problem = "max_distance_to_data_px must be >= 0";
  if (why) *why = problem;
  return problem.empty();
}

UncertaintyStudyResult RunUncertaintyStudy(const CameraIntrinsics& truth,
                                           const std::vector<View>& views,
                                           const std::vector<Rigid3>& cam_from_board,
                                           int image_width, int image_height,
                                           const UncertaintyStudyOptions& options,
                                           const std::vector<std::vector<View>>* measured_draws) {
  UncertaintyStudyResult result;
  std::string why;
  if (!options.Check(&why)) {
    result.message = "uncertainty study options: " + why;
    return result;
  }
  const int draws =
      measured_draws != nullptr ? static_cast<int>(measured_draws->size()) : options.draws;
  if (measured_draws != nullptr) {
    if (draws < 10) {
      result.message = "fewer than 10 measured draws (" + std::to_string(draws) + ")";
      return result;
    }
    for (const std::vector<View>& measured : *measured_draws) {
      if (measured.size() != views.size()) {
        result.message = "a measured draw has " + std::to_string(measured.size()) +
                         " views where the study has " + std::to_string(views.size());
        return result;
      }
    }
  }
  if (views.empty() || cam_from_board.size() != (options.shared_pose ? 1 : views.size())) {
    result.message = options.shared_pose ? "need one true pose" : "need one true pose per view";
    return result;
  }
  const RefineOptions refine = StudyRefineOptions(options);
  // The prediction at the truth: a solve of the noise-free views from the truth, with the true
  // sigma (it stays there; its covariance is the formula's at the truth).
  RefineOptions at_truth = refine;
  at_truth.known_pixel_sigma_px = options.pixel_sigma_px;
  const RefineResult exact = RefineCalibration(views, truth, cam_from_board, at_truth);
  if (!exact.IsUsable() || !exact.projection.IsSet()) {
    result.message = "the solve at the truth failed: " + exact.message;
    return result;
  }
  // The grid samples within reach of the data.
  const ImageGrid grid_shape = ImageGrid::Over(image_width, image_height, options.grid_cols);
  std::vector<Eigen::Vector2d> pixels;
  for (int j = 0; j < grid_shape.rows; ++j) {
    for (int i = 0; i < grid_shape.cols; ++i) {
      const Eigen::Vector2d q = grid_shape.PixelAt(i, j);
      PixelUncertainty u;
      if (!ProjectionUncertaintyAt(exact.intrinsics, exact.projection, q, options.distance_m, &u,
                                   nullptr)) {
        continue;
      }
      if (options.max_distance_to_data_px > 0) {
        double nearest = std::numeric_limits<double>::infinity();
        for (const View& view : views) {
          for (const Eigen::Vector2d& p : view.pixels) nearest = std::min(nearest, (p - q).norm());
        }
        if (nearest > options.max_distance_to_data_px) continue;
      }
      UncertaintyStudySample sample;
      sample.pixel = q;
      sample.predicted_px = u.worst_std_px;
      result.samples.push_back(sample);
      pixels.push_back(q);
    }
  }
  if (pixels.empty()) {
    result.message = "no grid sample within reach of the data";
    return result;
  }
  // The draws.
  std::vector<std::vector<Eigen::Vector2d>> reprojected(pixels.size());
  std::vector<std::vector<double>> draw_predictions(pixels.size());
  for (int d = 0; d < draws; ++d) {
    std::vector<View> noisy;
    if (measured_draws != nullptr) {
      noisy = (*measured_draws)[static_cast<size_t>(d)];
    } else {
      Rng rng(options.seed + static_cast<uint64_t>(d), RngStream::kPixelNoise);
      noisy = views;
      for (View& view : noisy) {
        for (Eigen::Vector2d& p : view.pixels) {
          p.x() += options.pixel_sigma_px * rng.Normal();
          p.y() += options.pixel_sigma_px * rng.Normal();
        }
      }
    }
    const RefineResult solved = RefineCalibration(noisy, truth, cam_from_board, refine);
    if (!solved.IsUsable() || !solved.projection.IsSet()) continue;
    std::vector<Eigen::Vector2d> draw(pixels.size());
    bool all = true;
    for (size_t s = 0; s < pixels.size() && all; ++s) {
      all =
          ReprojectThroughEstimate(truth, solved.intrinsics, cam_from_board, solved.cam_from_object,
                                   pixels[s], options.distance_m, &draw[s]);
    }
    if (!all) continue;
    ++result.draws_used;
    for (size_t s = 0; s < pixels.size(); ++s) {
      reprojected[s].push_back(draw[s]);
      PixelUncertainty own;
      if (ProjectionUncertaintyAt(solved.intrinsics, solved.projection, pixels[s],
                                  options.distance_m, &own, nullptr)) {
        draw_predictions[s].push_back(own.worst_std_px);
      }
    }
  }
  if (result.draws_used < 10) {
    result.message = "fewer than 10 re-solves converged";
    return result;
  }
  std::vector<double> ratios, draw_ratios, predicted, observed;
  for (size_t s = 0; s < pixels.size(); ++s) {
    const double observed_px = WorstStdPx(SampleCovariancePx2(reprojected[s]));
    UncertaintyStudySample& sample = result.samples[s];
    sample.observed_px = observed_px;
    sample.predicted_draws_px = Quantile(draw_predictions[s], 0.5);
    ratios.push_back(observed_px / sample.predicted_px);
    draw_ratios.push_back(observed_px / sample.predicted_draws_px);
    predicted.push_back(sample.predicted_px);
    observed.push_back(observed_px);
  }
  result.median_ratio = Quantile(ratios, 0.5);
  result.p10_ratio = Quantile(ratios, 0.1);
  result.p90_ratio = Quantile(ratios, 0.9);
  result.median_draw_ratio = Quantile(draw_ratios, 0.5);
  result.median_predicted_px = Quantile(predicted, 0.5);
  result.median_observed_px = Quantile(observed, 0.5);
  result.ok = true;
  return result;
}

}  // namespace calibench
