#include "detect/photometric_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "detect/tag_fit.h"

namespace calibench {
namespace photometric_internal {

// The PSF's std has settled when a step moves it less than this (px); it matters to the corners
// only through the edges' shape.
constexpr double kSigmaSettledPx = 5e-3;
// The robust pass needs this many flat pixels for its noise estimate; fewer, and it is skipped.
constexpr size_t kMinFlatPixels = 32;
// The lower quartile of |n| for n ~ N(0, 1): Phi^-1(5 / 8).
constexpr double kQuartileOfAbsNormal = 0.3186;
// The std of rounding to whole gray levels (1 / sqrt(12)): no image is less noisy.
constexpr double kRoundingStdGray = 0.2887;

namespace {
// The order statistic of rank floor(q (n - 1)) of n > 0 values (no interpolation).
double OrderStatistic(std::vector<double> values, double q) {
  const auto k = values.begin() + static_cast<long>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), k, values.end());
  return *k;
}
}  // namespace

bool TagFit::Start(const std::array<Eigen::Vector2d, 4>& initial, ParamVector* x,
                   PhotometricFitResult* result) {
  // The model plane's corners: the pixels, or their points on the tangent plane about the tag's
  // centre ray (the mean of the corners' unit rays).
  std::array<Eigen::Vector2d, 4> model_corners = initial;
  if (camera_ && !TangentPlane::AboutPixels(*camera_, initial, &plane_, &model_corners)) {
    result->failure = FitFailure::kDiverged;
    result->message =
        "a corner is outside the camera's valid region, or the corners span half the sphere";
    return false;
  }
  centre_.setZero();
  double perimeter = 0, pixel_perimeter = 0;
  for (int k = 0; k < 4; ++k) {
    centre_ += model_corners[k] / 4;
    perimeter += (model_corners[(k + 1) % 4] - model_corners[k]).norm();
    pixel_perimeter += (initial[(k + 1) % 4] - initial[k]).norm();
  }
  scale_ = perimeter / 8;  // Half the mean edge length.
  centre_jacobian_ = ModelJacobian(Eigen::Vector2d::Zero());
  px_per_unit_ = 1 / std::sqrt(std::abs(centre_jacobian_.determinant()));
  if (!(pixel_perimeter > 8) || !(scale_ > 0) || !centre_jacobian_.allFinite() ||
      !InitialHomography(initial, x)) {
    result->failure = FitFailure::kDiverged;
    result->message = "the detector's corners do not span a quadrilateral";
    return false;
  }
  (*x)[kSigma] = options_.initial_blur_px;
  if (!Classify(*x, result)) return false;
  // Levels: the medians of the pixels deep in black and of those far from every black rectangle.
  std::vector<double> dark, bright, all;
  for (const FitPixel& px : pixels_) {
    all.push_back(px.gray);
    if (px.num_rects == 0) (px.deep > 0 ? dark : bright).push_back(px.gray);
  }
  (*x)[kBlack] = dark.size() >= 8 ? OrderStatistic(dark, 0.5) : OrderStatistic(all, 0.05);
  (*x)[kWhite] = bright.size() >= 8 ? OrderStatistic(bright, 0.5) : OrderStatistic(all, 0.95);
  if (!((*x)[kWhite] - (*x)[kBlack] >= options_.min_contrast_gray)) {
    result->failure = FitFailure::kLowContrast;
    result->message =
        "the tag's region has a contrast of " + std::to_string((*x)[kWhite] - (*x)[kBlack]) +
        " gray levels (min_contrast_gray " + std::to_string(options_.min_contrast_gray) + ")";
    return false;
  }
  return true;
}

void TagFit::CornerCovariances(const ParamVector& x, const ParamMatrix& jtj,
                               double residual_variance,
                               const std::array<Eigen::Vector2d, 4>& corners,
                               PhotometricFitResult* result) const {
  // Cramer-Rao: cov(x) = sigma_n^2 (J^T J)^-1; corner k's derivative in G by the implicit
  // function theorem on pi(G c~) = q_k: dc / dG_ij = -A^-1 Jpi[:, i] c~_j, A = Jpi G[:, 0:2].
  ParamMatrix info = jtj;
  if (!options_.fit_shading) {
    for (int i : {kShadeX, kShadeY}) {
      info.row(i).setZero();
      info.col(i).setZero();
      info(i, i) = 1;
    }
  }
  const ParamMatrix covariance = residual_variance * info.ldlt().solve(ParamMatrix::Identity());
  const Eigen::Matrix3d g = HomographyOf(x);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d c = corners[k].homogeneous();
    const Eigen::Vector3d h = g * c;
    Eigen::Matrix<double, 2, 3> jpi;
    jpi << 1 / h.z(), 0, -h.x() / (h.z() * h.z()), 0, 1 / h.z(), -h.y() / (h.z() * h.z());
    const Eigen::Matrix2d a_inv = (jpi * g.leftCols<2>()).inverse();
    const Eigen::Matrix2d to_pixel = PixelJacobian(corners[k]);
    Eigen::Matrix<double, 2, 8> d;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (i == 2 && j == 2) continue;
        d.col(3 * i + j) = -to_pixel * a_inv * jpi.col(i) * c[j];
      }
    }
    result->corner_covariance_px2[k] = d * covariance.topLeftCorner<8, 8>() * d.transpose();
    result->crlb_px[k] = std::sqrt(std::max(0.0, result->corner_covariance_px2[k].trace() / 2));
  }
}

PhotometricFitResult TagFit::Run(const std::array<Eigen::Vector2d, 4>& initial) {
  PhotometricFitResult result;
  result.corners = initial;
  FitState state;
  state.x = ParamVector::Zero();
  if (!Start(initial, &state.x, &result)) return result;
  if (!Evaluate(state.x, &state.cost, &state.jtj, &state.jtr, &state.residuals)) {
    result.failure = FitFailure::kDiverged;
    result.message = "the initial homography is invalid over the tag's region";
    return result;
  }
  CornersOf(HomographyOf(state.x), &state.corners);
  if (!Minimize(initial, &state, &result)) return result;
  // A PSF wider than the one the pixels were classified with reaches farther: classify again.
  if (state.x[kSigma] > classified_sigma_ + kReclassifySigmaPx &&
      (!Classify(state.x, &result) ||
       !Evaluate(state.x, &state.cost, &state.jtj, &state.jtr, &state.residuals))) {
    if (result.ok()) result.failure = FitFailure::kDiverged;
    return result;
  }
  if (!LeaveOutDisagreeingPixels(initial, &state, &result)) return result;
  const double dof = std::max(1.0, static_cast<double>(pixels_.size()) - kNumParams);
  std::array<Eigen::Vector2d, 4> pixel_corners;
  if (!CheckSolution(state, initial, dof, &pixel_corners, &result)) return result;
  CornerCovariances(state.x, state.jtj, state.cost / dof, state.corners, &result);
  result.corners = pixel_corners;
  return result;
}

bool TagFit::StepCorners(const ParamVector& trial, const std::array<Eigen::Vector2d, 4>& initial,
                         const std::array<Eigen::Vector2d, 4>& corners, StepMoves* moves) const {
  // A step is tried only while every corner stays near the detector's: farther, the region
  // (and the cost of one evaluation) would grow without bound.
  bool valid =
      trial[kSigma] <= options_.max_blur_px && CornersOf(HomographyOf(trial), &moves->corners);
  moves->moved = moves->since_classified = 0;
  for (int k = 0; k < 4 && valid; ++k) {
    const Eigen::Vector2d c = ToPixel(moves->corners[k]);
    valid = (c - initial[k]).norm() <= 2 * options_.max_correction_px;
    moves->moved = std::max(moves->moved, px_per_unit_ * (moves->corners[k] - corners[k]).norm());
    moves->since_classified =
        std::max(moves->since_classified,
                 px_per_unit_ * (moves->corners[k] - classified_corners_[k]).norm());
  }
  return valid;
}

bool TagFit::Minimize(const std::array<Eigen::Vector2d, 4>& initial, FitState* state,
                      PhotometricFitResult* result) {
  ParamVector& x = state->x;
  PixelResiduals trial_residuals;  // Reused across the iterations.
  double lambda = 1e-4;
  bool converged = false;
  int it = 0;
  double last_moved = 0;  // Corner movement of the last accepted step (px); 0 before the first.
  for (; it < options_.max_iterations && !converged; ++it) {
    ParamMatrix a = state->jtj;
    for (int i = 0; i < kNumParams; ++i) a(i, i) = a(i, i) * (1 + lambda) + 1e-12;
    if (!options_.fit_shading) {
      for (int i : {kShadeX, kShadeY}) a(i, i) = 1;
    }
    const ParamVector step = a.ldlt().solve(state->jtr);
    ParamVector trial = x + step;
    trial[kSigma] = std::max(trial[kSigma], kMinSigmaPx);
    StepMoves moves;
    const bool valid = step.allFinite() && StepCorners(trial, initial, state->corners, &moves);
    const double moved = moves.moved;
    const bool sigma_settled = std::abs(trial[kSigma] - x[kSigma]) < kSigmaSettledPx;
    // The corners' error left after this step: the steps still to come, which shrink by
    // q = moved / last_moved each where Gauss-Newton converges at least linearly, sum to
    // moved q / (1 - q); where q is not small, no better bound than the step itself.
    const double q = last_moved > 0 ? moved / last_moved : 1.0;
    const double remaining = q < 0.5 ? moved * q / (1 - q) : moved;
    if (valid && remaining < options_.convergence_px && sigma_settled && lambda < 1e-2) {
      // The step is taken without another evaluation (the information J^T J and the cost at x are
      // those of the solution to within it).
      x = trial;
      state->corners = moves.corners;
      converged = true;
      break;
    }
    double trial_cost = 0;
    ParamMatrix trial_jtj;
    ParamVector trial_jtr;
    if (!valid || !Evaluate(trial, &trial_cost, &trial_jtj, &trial_jtr, &trial_residuals) ||
        !(trial_cost < state->cost)) {
      // At the minimum, steps below the tolerance may no longer lower the cost in floating point.
      converged = valid && moved < options_.convergence_px && sigma_settled;
      lambda *= 10;
      if (lambda > 1e8) break;
      continue;
    }
    x = trial;
    state->corners = moves.corners;
    last_moved = moved;
    state->cost = trial_cost;
    state->jtj = trial_jtj;
    state->jtr = trial_jtr;
    std::swap(state->residuals, trial_residuals);
    lambda = std::max(lambda / 10, 1e-9);
    converged = moved < options_.convergence_px && sigma_settled;
    // The pixels' rectangle lists may be stale: rebuild.
    if (moves.since_classified > kReclassifyPx ||
        x[kSigma] > classified_sigma_ + kReclassifySigmaPx) {
      if (!Classify(x, result)) return false;
      if (!Evaluate(x, &state->cost, &state->jtj, &state->jtr, &state->residuals)) break;
      converged = false;
    }
  }
  result->iterations += it;  // Summed over the fit and the robust pass's re-fits.
  if (converged) return true;
  result->failure =
      it >= options_.max_iterations ? FitFailure::kNotConverged : FitFailure::kDiverged;
  result->message =
      it >= options_.max_iterations
          ? "not converged in " + std::to_string(options_.max_iterations) + " iterations"
          : "no step lowers the cost";
  return false;
}

bool TagFit::LeaveOutDisagreeingPixels(const std::array<Eigen::Vector2d, 4>& initial,
                                       FitState* state, PhotometricFitResult* result) {
  const long width = image_.width, height = image_.height;
  auto left_out = [&](long key) {
    return std::binary_search(left_out_.begin(), left_out_.end(), key);
  };
  auto fail = [&](const std::string& message) {
    if (result->ok()) {
      result->failure = FitFailure::kDiverged;
      result->message = message;
    }
    return false;
  };
  for (int round = 0; round < options_.max_outlier_rounds; ++round) {
    // The residuals of the fit's last evaluation: at its solution, or one converged step before it
    // (a few thousandths of a pixel, far below what the thresholds tell apart).
    const PixelResiduals& residuals = state->residuals;
    const std::vector<double>& r = residuals.residual;
    // The noise std from the flat pixels (an edge's residuals hold the model's own misfit too), by
    // the lower quartile of |r| (kQuartileOfAbsNormal std for Gaussian noise): a covered corner
    // square can be half of a tag's flat pixels, which would double a median's estimate. Never
    // below the 8-bit rounding's std. Estimated again each round: a fit pulled by covered pixels
    // misses every edge a little, which the first round's flat pixels show too.
    std::vector<double> flat;
    for (size_t k = 0; k < r.size(); ++k) {
      if (residuals.flat[k]) flat.push_back(std::abs(r[k]));
    }
    if (flat.size() < kMinFlatPixels) break;  // Nothing to judge by.
    const double noise_std =
        std::max(OrderStatistic(std::move(flat), 0.25) / kQuartileOfAbsNormal, kRoundingStdGray);
    const double contrast = std::abs(state->x[kWhite] - state->x[kBlack]);
    const double threshold = std::max(options_.outlier_sigmas * noise_std,
                                      options_.outlier_contrast_fraction * contrast);
    // Each flat pixel that disagrees by threshold, and the rim around it that the PSF blurs into
    // its neighbours (edges included).
    const int rim =
        static_cast<int>(std::ceil(options_.outlier_rim_psf_sigmas * state->x[kSigma] + 0.5));
    const size_t before = left_out_.size();
    for (size_t k = 0; k < r.size(); ++k) {
      if (!residuals.flat[k] || !(std::abs(r[k]) > threshold)) continue;
      const long i = pixels_[k].key % width, j = pixels_[k].key / width;
      for (long dj = -rim; dj <= rim; ++dj) {
        for (long di = -rim; di <= rim; ++di) {
          if (di * di + dj * dj > rim * rim || i + di < 0 || i + di >= width || j + dj < 0 ||
              j + dj >= height) {
            continue;
          }
          left_out_.push_back((j + dj) * width + i + di);
        }
      }
    }
    std::sort(left_out_.begin(), left_out_.end());
    left_out_.erase(std::unique(left_out_.begin(), left_out_.end()), left_out_.end());
    // From the second round (the fit no longer pulled by what covers it): the covered area grows
    // over its 4-neighbours, edges included, that disagree by outlier_grow_sigmas noise std (a
    // hysteresis, as for Canny's edges), a pixel a pass and at most `rim` passes: the faint part
    // of a covering edge's blur that the rim missed, not a whole edge the model misses a little.
    if (round > 0) {
      const double grow_threshold = options_.outlier_grow_sigmas * noise_std;
      std::vector<long> grown;
      for (int pass = 0; pass < rim; ++pass) {
        grown.clear();
        for (size_t k = 0; k < r.size(); ++k) {
          const long key = pixels_[k].key, i = key % width;
          if (!(std::abs(r[k]) > grow_threshold) || left_out(key)) continue;
          if ((i > 0 && left_out(key - 1)) || (i + 1 < width && left_out(key + 1)) ||
              left_out(key - width) || left_out(key + width)) {
            grown.push_back(key);
          }
        }
        if (grown.empty()) break;
        const size_t old_size = left_out_.size();
        left_out_.insert(left_out_.end(), grown.begin(), grown.end());
        std::inplace_merge(left_out_.begin(), left_out_.begin() + static_cast<long>(old_size),
                           left_out_.end());
      }
    }
    if (left_out_.size() == before) break;  // Nothing new: the fit stands.
    if (!Classify(state->x, result)) return false;
    const long region = static_cast<long>(pixels_.size()) + left_out_pixels_;
    if (static_cast<double>(left_out_pixels_) > options_.max_outlier_fraction * region) {
      result->failure = FitFailure::kOccluded;
      result->message =
          std::to_string(left_out_pixels_) + " of the region's " + std::to_string(region) +
          " pixels disagree with the pattern (by more than " + std::to_string(threshold) +
          " gray levels where it is flat, or next to such) (max_outlier_fraction " +
          std::to_string(options_.max_outlier_fraction) + ")";
      return false;
    }
    if (!Evaluate(state->x, &state->cost, &state->jtj, &state->jtr, &state->residuals)) {
      return fail("the homography is invalid over the tag's region without the pixels left out");
    }
    if (!Minimize(initial, state, result)) return false;
  }
  // The last round's fit may have moved sigma past the classification's margin, as after the
  // first fit.
  if (state->x[kSigma] > classified_sigma_ + kReclassifySigmaPx &&
      (!Classify(state->x, result) ||
       !Evaluate(state->x, &state->cost, &state->jtj, &state->jtr, &state->residuals))) {
    return fail("the homography is invalid over the tag's region after the pass");
  }
  result->outlier_pixels = static_cast<int>(left_out_pixels_);
  return true;
}

bool TagFit::CheckSolution(const FitState& state, const std::array<Eigen::Vector2d, 4>& initial,
                           double dof, std::array<Eigen::Vector2d, 4>* pixel_corners,
                           PhotometricFitResult* result) const {
  const ParamVector& x = state.x;
  result->pixels = static_cast<int>(pixels_.size());
  result->blur_px = x[kSigma];
  result->black_gray = x[kBlack];
  result->white_gray = x[kWhite];
  result->residual_rms_gray = std::sqrt(state.cost / dof);
  const double contrast = x[kWhite] - x[kBlack];
  if (!(contrast >= options_.min_contrast_gray) ||
      !(contrast >= options_.min_contrast_to_residual * result->residual_rms_gray)) {
    result->failure = FitFailure::kLowContrast;
    result->message = "fitted contrast " + std::to_string(contrast) + " gray levels against a " +
                      std::to_string(result->residual_rms_gray) +
                      " gray-level residual RMS (min_contrast_gray " +
                      std::to_string(options_.min_contrast_gray) + ", min_contrast_to_residual " +
                      std::to_string(options_.min_contrast_to_residual) + ")";
    return false;
  }
  for (int k = 0; k < 4; ++k) {
    (*pixel_corners)[k] = ToPixel(state.corners[k]);
    const double moved = ((*pixel_corners)[k] - initial[k]).norm();
    if (!(moved <= options_.max_correction_px)) {
      result->failure = FitFailure::kMoved;
      result->message = "corner " + std::to_string(k) + " moved " + std::to_string(moved) +
                        " px from the detector's (max_correction_px " +
                        std::to_string(options_.max_correction_px) + ")";
      return false;
    }
  }
  return true;
}

}  // namespace photometric_internal

using photometric_internal::TagFit;

bool PhotometricFitOptions::Check(std::string* why) const {
  std::string msg;
  if (max_iterations < 1) msg = "max_iterations must be >= 1";
  if (!(max_blur_px > 0 && max_blur_px <= 20)) msg = "max_blur_px must lie in (0, 20]";
  if (!(initial_blur_px > 0 && initial_blur_px < max_blur_px))
    msg = "initial_blur_px must lie in (0, max_blur_px)";
  if (!(max_correction_px > 0)) msg = "max_correction_px must be > 0";
  if (!(min_contrast_gray > 0)) msg = "min_contrast_gray must be > 0";
  if (!(min_contrast_to_residual >= 0)) msg = "min_contrast_to_residual must be >= 0";
  if (!(convergence_px > 0)) msg = "convergence_px must be > 0";
  if (min_pixels < photometric_internal::kNumParams + 1) msg = "min_pixels must be > 13";
  if (!(max_outside_fraction >= 0 && max_outside_fraction < 1))
    msg = "max_outside_fraction must lie in [0, 1)";
  if (!(outlier_sigmas > 0)) msg = "outlier_sigmas must be > 0";
  if (!(outlier_contrast_fraction >= 0)) msg = "outlier_contrast_fraction must be >= 0";
  if (max_outlier_rounds < 0) msg = "max_outlier_rounds must be >= 0";
  if (!(outlier_grow_sigmas > 0 && outlier_grow_sigmas <= outlier_sigmas))
    msg = "outlier_grow_sigmas must lie in (0, outlier_sigmas]";
  if (!(outlier_rim_psf_sigmas >= 0 && outlier_rim_psf_sigmas <= 10))
    msg = "outlier_rim_psf_sigmas must lie in [0, 10]";
  if (!(max_outlier_fraction >= 0 && max_outlier_fraction < 1))
    msg = "max_outlier_fraction must lie in [0, 1)";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

const char* FitFailureName(FitFailure failure) {
  static constexpr std::array<const char*, kNumFitFailures> kNames = {
      "none",     "image_border",  "low_contrast", "too_few_pixels",
      "diverged", "not_converged", "moved",        "occluded"};
  const int i = static_cast<int>(failure);
  return i >= 0 && i < kNumFitFailures ? kNames[i] : "unknown";
}

std::string FormatFitFailures(const std::array<int, kNumFitFailures>& counts) {
  std::string text;
  for (int f = 1; f < kNumFitFailures; ++f) {
    if (counts[f] == 0) continue;
    if (!text.empty()) text += ", ";
    text +=
        std::string(FitFailureName(static_cast<FitFailure>(f))) + " " + std::to_string(counts[f]);
  }
  return text;
}

PhotometricFitResult FitTagPhotometric(const GrayImageView& image, const TagPattern& pattern,
                                       const std::array<Eigen::Vector2d, 4>& initial_corners,
                                       const PhotometricFitOptions& options,
                                       const CameraIntrinsics* camera) {
  PhotometricFitResult result;
  result.corners = initial_corners;
  if (!options.Check(&result.message)) {
    result.failure = FitFailure::kDiverged;
    return result;
  }
  if (pattern.black.empty() || pattern.width_cells < 1) {
    result.failure = FitFailure::kDiverged;
    result.message = "the tag pattern has no black";
    return result;
  }
  if (camera && !camera->Check(&result.message)) {
    result.failure = FitFailure::kDiverged;
    return result;
  }
  TagFit fit(image, pattern, options, camera && camera->IsDistorted() ? camera : nullptr);
  return fit.Run(initial_corners);
}

}  // namespace calibench
