// Do two calibrations describe the same camera? The projection difference of two camera models
// over their common field, after the rotation their camera frames may differ by is fitted out, as
// mrcal-show-projection-diff does, against the two models' projection uncertainty
// (batch/projection_uncertainty.h) where their files carry it.
//
// Both cameras are taken to share pixel coordinates (the same sensor). When B's image is A's
// scaled by one factor k in both directions (a binned or downsampled copy: TUM VI publishes its
// 1024 px camera at 512 px), B is first taken to A's pixels (ScaleCamera); other sizes are
// compared over the pixels both images hold. Over a grid of A's image:
//   rays r_A(q) = unproject_A(q), r_B(q) = unproject_B(q) where both unproject;
//   R = argmin sum w(q) |r_B(q) - R r_A(q)|^2 (weighted Procrustes; w = 1 / (sigma_A^2 +
//       sigma_B^2) when both carry an uncertainty, else 1; then once more without the samples
//       whose difference exceeds 5x the median: a region where one model is far off does not
//       pull the rotation);
//   difference(q) = |project_B(R r_A(q)) - q| (px), where it falls inside B's image;
//   sigma(q) = sqrt(sigma_A(q)^2 + sigma_B(q')^2), each the worst-direction std of its model at
//       q (A) and at q' = project_B(R r_A(q)) (B), rays at `distance_m`; a model whose file carries
//       no uncertainty (a published calibration) counts 0: the verdict is then against the other
//       one's alone, a lower bound of the combined figure, and says so.
// Verdict: "agree" when the difference is within kAgreeSigmas * sigma on at least
// kAgreeFraction of the common field; otherwise "differ", with the share of the field and the
// region where difference / sigma is worst; without an uncertainty on either side, the
// difference alone (said so). The distance matters only through the uncertainty and the fitted
// rotation's weights: the projection of a ray is the same at any distance when the frames share
// their origin.
#pragma once

#include <limits>
#include <string>

#include "calib/camera_file.h"
#include "camera/image_grid.h"

namespace calibench {

// A 2D difference of independent normal errors with per-axis std <= sigma lies within 2 sigma
// with probability >= 86 % (Rayleigh); 90 % of the field within it allows for the worst-direction
// sigma being an upper bound in one axis only.
constexpr double kAgreeSigmas = 2.0;
constexpr double kAgreeFraction = 0.9;

struct CompareOptions {
  int grid_cols = 60;                                           // Samples across A's image.
  double distance_m = std::numeric_limits<double>::infinity();  // Target units; infinity: rays.
  bool fit_rotation = true;  // false: the camera frames are taken as the same.
  bool Check(std::string* why) const;
};

struct CameraComparison {
  bool ok = false;
  std::string message;                                     // Why not ok.
  Eigen::Matrix3d b_from_a = Eigen::Matrix3d::Identity();  // The fitted rotation.
  double rotation_deg = 0.0;                               // Its angle.
  ImageGrid difference_px;       // Over A's image; NaN outside the common field.
  ImageGrid sigma_px;            // Combined uncertainty; NaN where a model has none.
  int common_samples = 0;        // Grid samples in the common field.
  double common_fraction = 0.0;  // Of A's grid samples.
  double median_px = std::numeric_limits<double>::quiet_NaN();
  double p90_px = std::numeric_limits<double>::quiet_NaN();
  double max_px = std::numeric_limits<double>::quiet_NaN();
  bool a_has_uncertainty = false, b_has_uncertainty = false;
  // A file's uncertainty is formal only (CameraFile::projection_source): said beside the verdict.
  bool a_formal_only = false, b_formal_only = false;
  // With both uncertainties: the share of the common field within kAgreeSigmas * sigma, and the
  // median of difference / sigma.
  double within_fraction = std::numeric_limits<double>::quiet_NaN();
  double median_ratio = std::numeric_limits<double>::quiet_NaN();
  enum class Verdict { kAgree, kDiffer, kNoUncertainty };
  Verdict verdict = Verdict::kNoUncertainty;
  std::string worst_region;        // Where the difference (px) is largest.
  std::string worst_ratio_region;  // Where difference / sigma is largest (with an uncertainty).
  double b_scale = 1.0;            // The factor B was scaled by to A's pixels (1: none).
};

// `camera` on an image k times larger in both directions: focal lengths times k, the principal
// point at k (c + 0.5) - 0.5 (pixel centres), image size times k, and its projection covariance
// carried along (the pixel-valued intrinsics' rows times k).
CameraFile ScaleCamera(const CameraFile& camera, double k);

CameraComparison CompareCameras(const CameraFile& a, const CameraFile& b,
                                const CompareOptions& options);

// The verdict and its numbers as lines for a terminal (`a_name`, `b_name`: the files).
std::string FormatComparison(const CameraComparison& c, const std::string& a_name,
                             const std::string& b_name);

}  // namespace calibench
