// Two calibrations compared over their common field (calib/compare_cameras.h).
#include "calib/compare_cameras.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "batch/projection_uncertainty.h"
#include "calib/calibration_pictures.h"

namespace calibench {
namespace {

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(std::lround(q * static_cast<double>(values.size() - 1)))];
}

bool InsideImage(const Eigen::Vector2d& q, int width, int height) {
  return q.x() >= -0.5 && q.y() >= -0.5 && q.x() <= width - 0.5 && q.y() <= height - 0.5;
}

// The worst-direction std of `camera`'s projection at `pixel`, NaN without an uncertainty.
double SigmaAt(const CameraFile& camera, const Eigen::Vector2d& pixel, double distance_m) {
  PixelUncertainty u;
  if (!camera.projection.IsSet() || !ProjectionUncertaintyAt(camera.intrinsics, camera.projection,
                                                             pixel, distance_m, &u, nullptr)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return u.worst_std_px;
}

// One common-field sample: A's pixel and both rays.
struct Sample {
  int i, j;
  Eigen::Vector2d pixel;
  Eigen::Vector3d ray_a, ray_b;
  double sigma_a;
};

// argmin_R sum w |b - R a|^2 over unit rays (Kabsch).
Eigen::Matrix3d FitRotation(const std::vector<Sample>& samples, const std::vector<double>& weight) {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (size_t s = 0; s < samples.size(); ++s) {
    h += weight[s] * samples[s].ray_a * samples[s].ray_b.transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixV() * d * svd.matrixU().transpose();
}

}  // namespace

bool CompareOptions::Check(std::string* why) const {
  std::string problem;
  if (grid_cols < 4) problem = "grid_cols must be at least 4";
  if (!(distance_m > 0)) problem = "distance_m must be positive (or infinity)";
  if (why) *why = problem;
  return problem.empty();
}

CameraFile ScaleCamera(const CameraFile& camera, double k) {
  CameraFile scaled = camera;
  CameraIntrinsics& i = scaled.intrinsics;
  i.fku_px *= k, i.fkv_px *= k;
  i.u0_px = k * (i.u0_px + 0.5) - 0.5;
  i.v0_px = k * (i.v0_px + 0.5) - 0.5;
  scaled.image_width = static_cast<int>(std::lround(k * camera.image_width));
  scaled.image_height = static_cast<int>(std::lround(k * camera.image_height));
  for (int p : {0, 1, 3, 4}) {
    if (std::isfinite(scaled.intrinsics_std[p])) scaled.intrinsics_std[p] *= k;
  }
  if (camera.projection.IsSet()) {
    Eigen::Matrix<double, ProjectionCovariance::kSize, 1> d =
        Eigen::Matrix<double, ProjectionCovariance::kSize, 1>::Ones();
    for (int p : {0, 1, 3, 4}) d[p] = k;
    scaled.projection.covariance = d.asDiagonal() * camera.projection.covariance * d.asDiagonal();
    scaled.projection.sigma_px *= k;
  }
  return scaled;
}

CameraComparison CompareCameras(const CameraFile& a, const CameraFile& b_given,
                                const CompareOptions& options) {
  CameraComparison c;
  if (!options.Check(&c.message)) return c;
  if (a.image_width <= 0 || a.image_height <= 0 || b_given.image_width <= 0 ||
      b_given.image_height <= 0) {
    c.message = "both cameras need an image size";
    return c;
  }
  // A copy of A's image at another scale: B taken to A's pixels.
  const double kx = static_cast<double>(a.image_width) / b_given.image_width;
  const double ky = static_cast<double>(a.image_height) / b_given.image_height;
  if (kx != 1.0 && std::abs(kx - ky) < 1e-9) c.b_scale = kx;
  const CameraFile b = c.b_scale != 1.0 ? ScaleCamera(b_given, c.b_scale) : b_given;
  c.a_has_uncertainty = a.projection.IsSet();
  c.b_has_uncertainty = b.projection.IsSet();
  c.a_formal_only = c.a_has_uncertainty && a.projection_source == "formal";
  c.b_formal_only = c.b_has_uncertainty && b.projection_source == "formal";
  c.difference_px = ImageGrid::Over(a.image_width, a.image_height, options.grid_cols);
  c.sigma_px = c.difference_px;
  std::vector<Sample> samples;
  for (int j = 0; j < c.difference_px.rows; ++j) {
    for (int i = 0; i < c.difference_px.cols; ++i) {
      Sample s{i, j, c.difference_px.PixelAt(i, j), {}, {}, 0};
      if (!InsideImage(s.pixel, b.image_width, b.image_height) ||
          !UnprojectToRay(a.intrinsics, s.pixel, &s.ray_a) ||
          !UnprojectToRay(b.intrinsics, s.pixel, &s.ray_b)) {
        continue;
      }
      s.sigma_a = SigmaAt(a, s.pixel, options.distance_m);
      samples.push_back(s);
    }
  }
  if (samples.size() < 10) {
    c.message = "the two cameras share fewer than 10 grid samples of field";
    return c;
  }
  const bool any = c.a_has_uncertainty || c.b_has_uncertainty;
  // A model without an uncertainty counts 0 (header comment).
  const auto variance = [&](double sigma_a, double sigma_b) {
    return (c.a_has_uncertainty ? sigma_a * sigma_a : 0.0) +
           (c.b_has_uncertainty ? sigma_b * sigma_b : 0.0);
  };
  // Weights: 1 / sigma^2, B's taken at the same pixel for the fit.
  std::vector<double> weight(samples.size(), 1.0);
  if (any) {
    for (size_t s = 0; s < samples.size(); ++s) {
      const double var =
          variance(samples[s].sigma_a, SigmaAt(b, samples[s].pixel, options.distance_m));
      weight[s] = std::isfinite(var) && var > 0 ? 1.0 / var : 0.0;
    }
  }
  const auto differences = [&](const Eigen::Matrix3d& r, std::vector<double>* d,
                               std::vector<Eigen::Vector2d>* q_b) {
    d->assign(samples.size(), std::numeric_limits<double>::quiet_NaN());
    q_b->assign(samples.size(), Eigen::Vector2d::Zero());
    for (size_t s = 0; s < samples.size(); ++s) {
      Eigen::Vector2d q;
      if (ProjectPoint(b.intrinsics, r * samples[s].ray_a, &q) &&
          InsideImage(q, b.image_width, b.image_height)) {
        (*d)[s] = (q - samples[s].pixel).norm();
        (*q_b)[s] = q;
      }
    }
  };
  std::vector<double> d;
  std::vector<Eigen::Vector2d> q_b;
  if (options.fit_rotation) {
    c.b_from_a = FitRotation(samples, weight);
    differences(c.b_from_a, &d, &q_b);
    std::vector<double> finite;
    for (double v : d) {
      if (std::isfinite(v)) finite.push_back(v);
    }
    const double cut = 5.0 * Quantile(finite, 0.5);
    for (size_t s = 0; s < samples.size(); ++s) {
      if (!(d[s] <= cut)) weight[s] = 0.0;
    }
    c.b_from_a = FitRotation(samples, weight);
  }
  differences(c.b_from_a, &d, &q_b);
  c.rotation_deg = Eigen::AngleAxisd(c.b_from_a).angle() * 180.0 / M_PI;
  std::vector<double> finite, ratios;
  ImageGrid ratio_grid = c.difference_px;
  int within = 0;
  for (size_t s = 0; s < samples.size(); ++s) {
    if (!std::isfinite(d[s])) continue;
    c.difference_px.At(samples[s].i, samples[s].j) = d[s];
    finite.push_back(d[s]);
    if (!any) continue;
    const double sigma =
        std::sqrt(variance(samples[s].sigma_a, SigmaAt(b, q_b[s], options.distance_m)));
    if (!std::isfinite(sigma) || sigma <= 0) continue;
    c.sigma_px.At(samples[s].i, samples[s].j) = sigma;
    ratio_grid.At(samples[s].i, samples[s].j) = d[s] / sigma;
    ratios.push_back(d[s] / sigma);
    if (d[s] <= kAgreeSigmas * sigma) ++within;
  }
  c.common_samples = static_cast<int>(finite.size());
  c.common_fraction = static_cast<double>(finite.size()) / c.difference_px.values.size();
  if (finite.empty()) {
    c.message = "no grid sample of A projects into B's image";
    return c;
  }
  c.median_px = Quantile(finite, 0.5);
  c.p90_px = Quantile(finite, 0.9);
  c.max_px = *std::max_element(finite.begin(), finite.end());
  if (!ratios.empty()) {
    c.within_fraction = static_cast<double>(within) / ratios.size();
    c.median_ratio = Quantile(ratios, 0.5);
    c.verdict = c.within_fraction >= kAgreeFraction ? CameraComparison::Verdict::kAgree
                                                    : CameraComparison::Verdict::kDiffer;
    c.worst_ratio_region = WorstRegion(ratio_grid, nullptr);
  }
  c.worst_region = WorstRegion(c.difference_px, nullptr);
  c.ok = true;
  return c;
}

std::string FormatComparison(const CameraComparison& c, const std::string& a_name,
                             const std::string& b_name) {
  if (!c.ok) return "comparison failed: " + c.message + "\n";
  char line[1024];
  std::string text;
  if (c.b_scale != 1.0) {
    std::snprintf(line, sizeof(line),
                  "note: %s's image is %s's scaled by %.4g: %s taken to %s's pixels (f x k, c at "
                  "k (c + 0.5) - 0.5)\n",
                  a_name.c_str(), b_name.c_str(), c.b_scale, b_name.c_str(), a_name.c_str());
    text += line;
  }
  std::snprintf(line, sizeof(line),
                "Projection difference of %s against %s (rays at the grid of %s's image, %.0f %% "
                "of it common), after a fitted rotation of %.3f deg:\n  median %.3f px, 90th "
                "percentile %.3f px, max %.3f px (largest: %s)\n",
                b_name.c_str(), a_name.c_str(), a_name.c_str(), 100 * c.common_fraction,
                c.rotation_deg, c.median_px, c.p90_px, c.max_px,
                c.worst_region.empty() ? "-" : c.worst_region.c_str());
  text += line;
  // Whose uncertainty the verdict is against.
  const std::string whose = c.a_has_uncertainty && c.b_has_uncertainty ? "their uncertainty"
                            : c.a_has_uncertainty
                                ? a_name + "'s uncertainty alone (" + b_name + " carries none)"
                                : b_name + "'s uncertainty alone (" + a_name + " carries none)";
  switch (c.verdict) {
    case CameraComparison::Verdict::kAgree:
      std::snprintf(line, sizeof(line),
                    "Verdict: AGREE within %s: %.0f %% of the common field within %.0f sigma "
                    "(median difference / sigma %.2f)\n",
                    whose.c_str(), 100 * c.within_fraction, kAgreeSigmas, c.median_ratio);
      break;
    case CameraComparison::Verdict::kDiffer:
      std::snprintf(line, sizeof(line),
                    "Verdict: DIFFER beyond %s: only %.0f %% of the common field within %.0f "
                    "sigma (median difference / sigma %.2f; worst against sigma in the %s)\n",
                    whose.c_str(), 100 * c.within_fraction, kAgreeSigmas, c.median_ratio,
                    c.worst_ratio_region.c_str());
      break;
    case CameraComparison::Verdict::kNoUncertainty:
      std::snprintf(line, sizeof(line),
                    "Verdict: difference only: neither %s nor %s carries a projection uncertainty "
                    "(a camera file calibench's calibrate writes has it), so agreement cannot be "
                    "judged\n",
                    a_name.c_str(), b_name.c_str());
      break;
  }
  text += line;
  for (const auto& [formal, name] :
       {std::make_pair(c.a_formal_only, a_name), std::make_pair(c.b_formal_only, b_name)}) {
    if (formal && c.verdict != CameraComparison::Verdict::kNoUncertainty) {
      text += "note: " + name +
              "'s uncertainty is formal only (no leave-one-view-out scale): on real images it is "
              "usually 2-9x too small, and a DIFFER may be that\n";
    }
  }
  return text;
}

}  // namespace calibench
