// Photometric refinement of one decoded AprilTag: the tag's known pattern, drawn through a
// homography, blurred by a Gaussian PSF and integrated over the pixel box, fitted to every pixel
// of the tag's region. There is no edge window: the corners are the model's corners.
//
// The model (the pattern in tag coordinates, the blurred edge profile and the black fraction b(p)
// of a pixel) is detect/tag_model.h's. The model of pixel p (gray levels) is
//   I(p) = s(p) [w + (k - w) b(p)],   s(p) = 1 + g . (p - c0) / S         (linear shading)
// with k, w the black and white levels.
//
// Parameters (13): the image -> tag homography G (8 entries, G_22 = 1, between normalised pixel
// and tag coordinates), sigma, k, w and the shading g. Levenberg-Marquardt with analytic
// Jacobians: d_e = S (l . p^) / |l_xy| with l = G^T m_e (m_e the tag line), linear in G.
// The fit uses the pixels within R + 0.5 px of a rectangle's edge (R = 3.5 sigma + 0.75, the
// profile's reach; the 0.5 px lets the corners move before the pixels are classified again) and
// at least R px inside the known region: the black square and a white margin of
// `white_margin_cells` (an AprilGrid's gap to the next tag). Saturated pixels are censored. The
// residual variance holds whatever the model does not explain (a renderer's sampled blur kernel,
// vignetting beyond linear): the bound is then conservative.
//
// Pixels that disagree (occlusion, clutter): the region includes the white margin around the
// black square and, on an AprilGrid, the corner squares beside it. Where something else covers
// part of it (a finger, another board in front, a reflection) those pixels pull the least-squares
// fit: another board over a grid's outer corner squares moved its corners by 0.5 px. After the
// fit converges, a pixel where the pattern is flat (its slope below kFlatSlopePerPx of the
// contrast per px: 2.2 s from an edge at s = 0.8 px, 1.8 s at 1.6 px) whose residual r exceeds
// both outlier_sigmas times the noise std (from the lower quartile of the flat pixels' |r|, robust
// to those very pixels; never below the 8-bit rounding's 0.29) and outlier_contrast_fraction of
// the fitted contrast |w - k| is left out with the pixels within outlier_rim_psf_sigmas PSF std of
// it (the covering edge's blurred rim, too faint to be found by its own residual), and the fit
// runs again from there; repeated (at most max_outlier_rounds) while pixels are left out. From
// the second round (the fit no longer pulled) the covered area also grows, a pixel a pass and at
// most a rim's width, over the 4-neighbours, edges included, that disagree by outlier_grow_sigmas
// noise std. An edge pixel alone is never a seed: a model that misses an edge's shape (an unknown
// lens bending it, a sharpened image's halo) shows there. So a cover that reaches no flat pixel
// (within ~2 PSF std of the pattern's edges only, or in a blur so wide that little is flat) is
// not found. A misplaced edge of the pattern itself moves a pixel by at most 0.4 contrast
// (shift / s), a 25th of the contrast for a 0.1 px shift at s = 1: only something the pattern
// cannot produce reaches a quarter of it. With nothing left out the fit is the plain
// least-squares one, bit for bit. Left out are never more than max_outlier_fraction of the
// region's pixels: more, and the tag is refused as occluded.
//
// The Cramer-Rao bound of each corner: the corners are functions of G; their covariance is
// D_k [sigma_n^2 (J^T J)^-1]_GG D_k^T, with sigma_n^2 the residual variance (on N - 13 degrees of
// freedom) and D_k the corner's derivative with respect to G. `crlb_px` is its per-axis RMS std,
// sqrt(trace / 2).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "detect/tag_model.h"
#include "sim/render.h"
#include "sim/tag_family.h"

namespace calibench {

struct PhotometricFitOptions {
  int max_iterations = 30;          // LM iterations (a step refused counts as one).
  double initial_blur_px = 0.5;     // Start of sigma (PSF std, px).
  double max_blur_px = 4.0;         // A step to a wider PSF is refused (the region grows with it).
  double max_correction_px = 1.5;   // A corner moving farther from the detector's is refused.
  double min_contrast_gray = 10.0;  // w - k below this: no tag to fit.
  // The fitted contrast over the residual RMS below this: the pattern does not explain the pixels
  // (no tag, occluded, or another pattern).
  double min_contrast_to_residual = 5.0;
  // Converged when the corners' error left after the next Gauss-Newton step is below this (px):
  // that step is taken without another evaluation, and what remains is estimated from the ratio
  // q of its size to the previous step's (moved q / (1 - q)), or is the step itself when q > 1/2.
  double convergence_px = 5e-4;
  bool fit_shading = true;  // The linear shading g (vignetting, uneven light).
  int min_pixels = 64;      // Fewer pixels in the region: refused.
  // Fraction of the region's pixels that may fall outside the image before the tag is refused.
  double max_outside_fraction = 0.25;
  // Pixels that disagree with the pattern (header): a flat pixel is left out when |r| exceeds
  // both of these (noise std from the flat pixels' lower quartile of |r|; fraction of the fitted
  // contrast), then the fit runs again.
  double outlier_sigmas = 6.0;
  double outlier_contrast_fraction = 0.25;
  // A pixel beside those left out goes when it disagrees by this many noise std (header).
  double outlier_grow_sigmas = 4.0;
  // The pixels within this many PSF std (+ half a pixel) of one left out go too: the blurred rim
  // of whatever covers the pattern.
  double outlier_rim_psf_sigmas = 4.0;
  int max_outlier_rounds = 3;          // Fits again at most this often (0: no robust pass).
  double max_outlier_fraction = 0.25;  // Left out more of the region than this: refused.
  bool Check(std::string* why) const;
};

// Why a fit was refused; kNone when it succeeded.
enum class FitFailure {
  kNone,
  kImageBorder,   // Too much of the region outside the image.
  kLowContrast,   // Contrast below min_contrast_gray, or below min_contrast_to_residual x the
                  // residual RMS (saturated, constant, or not this tag).
  kTooFewPixels,  // The region has fewer than min_pixels usable pixels.
  kDiverged,      // LM could not reduce the cost, or the homography became degenerate.
  kNotConverged,  // max_iterations reached.
  kMoved,         // A corner moved more than max_correction_px.
  kOccluded,      // More than max_outlier_fraction of the region disagrees with the pattern.
};
constexpr int kNumFitFailures = 8;
const char* FitFailureName(FitFailure failure);  // "none", "image_border", ...
// Refusals counted by FitFailure (index 0, kNone, ignored): "diverged 1, moved 2", or empty.
std::string FormatFitFailures(const std::array<int, kNumFitFailures>& counts);

struct PhotometricFitResult {
  FitFailure failure = FitFailure::kNone;
  std::string message;
  int iterations = 0;      // LM iterations, the robust pass's re-fits included.
  int pixels = 0;          // Pixels in the fit.
  int outlier_pixels = 0;  // Left out as disagreeing with the pattern (header).
  std::array<Eigen::Vector2d, 4> corners;
  std::array<Eigen::Matrix2d, 4> corner_covariance_px2;
  std::array<double, 4> crlb_px{};  // sqrt(trace(cov) / 2) per corner.
  double blur_px = 0, black_gray = 0, white_gray = 0;
  double residual_rms_gray = 0;
  bool ok() const { return failure == FitFailure::kNone; }
};

// Fits `pattern` to `image` from the detector's corners (calibench convention, detector order).
// With a distorted `camera` (lens-aware fit; every family, past 90 deg from the axis too) the
// homography maps the tangent plane about the tag's centre ray (detect/tangent_plane.h; c the mean
// of the detector's corners' unit rays) to the tag: a ray r is the point (e1 . r, e2 . r) / (c . r)
// there, and the tag's edges are straight. Every distance above is then measured in pixels
// through the lens: d = (l . u~(p)) / |J(p)^T l_xy|, u(p) the plane point of pixel p's ray
// (UnprojectToRay) and J = du/dp (the inverse of the central differences of the projection,
// ProjectPoint), so the model's edges bend as the lens bends them (to second order: d + spread
// d^2 / 2 where J changes across the edge; the blurred profile shifted by the edge's curvature;
// tag_fit.h PatternLines). A pinhole camera (or none) fits in pixels. Never throws;
// result.failure says why a fit was refused (corners then unchanged).
PhotometricFitResult FitTagPhotometric(const GrayImageView& image, const TagPattern& pattern,
                                       const std::array<Eigen::Vector2d, 4>& initial_corners,
                                       const PhotometricFitOptions& options,
                                       const CameraIntrinsics* camera = nullptr);

}  // namespace calibench
