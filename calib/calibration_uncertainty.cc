// Where in the image a calibration can be trusted (calib/calibration_uncertainty.h).
#include "calib/calibration_uncertainty.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "batch/projection_jacobian.h"
#include "calib/calibration_pictures.h"

namespace calibench {
namespace {

// The leave-one-view-out spread of the projection over the formal map's grid.
std::optional<UncertaintyMap> JackknifeMap(const RefineResult& fit, const JackknifeResult& jack,
                                           const ImageGrid& shape, double distance_m) {
  const size_t n = jack.leave_one_out.size();
  if (!jack.IsUsable() || n < 2 || jack.leave_one_out_poses.size() != n ||
      fit.cam_from_object.size() != n) {
    return std::nullopt;
  }
  // Refit i's reference poses: the full fit's, view i left out.
  std::vector<std::vector<Rigid3>> reference(n);
  for (size_t i = 0; i < n; ++i) {
    for (size_t v = 0; v < n; ++v) {
      if (v != i) reference[i].push_back(fit.cam_from_object[v]);
    }
  }
  UncertaintyMap map;
  map.worst_std_px = shape;
  std::fill(map.worst_std_px.values.begin(), map.worst_std_px.values.end(),
            std::numeric_limits<double>::quiet_NaN());
  std::vector<Eigen::Vector2d> q(n);
  for (int j = 0; j < shape.rows; ++j) {
    for (int c = 0; c < shape.cols; ++c) {
      bool all = true;
      for (size_t i = 0; i < n && all; ++i) {
        all = ReprojectThroughEstimate(fit.intrinsics, jack.leave_one_out[i], reference[i],
                                       jack.leave_one_out_poses[i], shape.PixelAt(c, j), distance_m,
                                       &q[i]);
      }
      if (!all) continue;
      // The jackknife's (n - 1) / n sum of squares: (n - 1)^2 / n times the sample covariance.
      const double n_views = static_cast<double>(n);
      map.worst_std_px.At(c, j) =
          WorstStdPx((n_views - 1) * (n_views - 1) / n_views * SampleCovariancePx2(q));
    }
  }
  SummariseUncertaintyMap(&map);
  return map;
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// The held-out check of the header comment, into u->held_out_*: the observed residual of the
// pose-only fit of view i through refit i, against the expectation of its squared norm.
void HeldOutViews(const std::vector<View>& views, const RefineOptions& refine,
                  const RefineResult& fit, const JackknifeResult& jack, CalibrationUncertainty* u) {
  RefineOptions pose_only = refine;
  pose_only.fix_intrinsics = true;
  pose_only.compute_covariance = false;
  pose_only.view_names.clear();
  const double sigma_px = u->quoted.sigma_px / u->scale;  // sigma_hat, per coordinate.
  const double noise_var = sigma_px * sigma_px;
  // Refit i has one view fewer than the fit whose covariance is at hand: N / (N - 1) times it.
  const double refit_factor = views.size() > 1 ? views.size() / (views.size() - 1.0) : 1.0;
  const auto params = fit.intrinsics.Params();
  std::vector<double> rms, formal_ratio, quoted_ratio;
  double excess_sum = 0, calibration_sum = 0;
  for (size_t i = 0; i < views.size(); ++i) {
    const View& view = views[i];
    const int n = static_cast<int>(view.points.size());
    if (n < 4) continue;
    const RefineResult held =
        RefineCalibration({view}, jack.leave_one_out[i], {fit.cam_from_object[i]}, pose_only);
    if (!held.IsUsable()) continue;
    // J_theta (2n x 10) and the pose columns (2n x 6) at the full fit.
    Eigen::MatrixXd j_theta(2 * n, 10), j_pose(2 * n, 6);
    const Rigid3& pose = fit.cam_from_object[i];
    bool ok = true;
    for (int k = 0; k < n && ok; ++k) {
      const Eigen::Vector3d turned = pose.rotation * view.points[k];
      ProjectionJacobian pj;
      ok = ProjectWithJacobian(fit.intrinsics.family, params.data(), turned + pose.translation,
                               true, &pj);
      j_theta.middleRows<2>(2 * k) = pj.d_intrinsics;
      j_pose.block<2, 3>(2 * k, 0) = -pj.d_point * Hat(turned);
      j_pose.block<2, 3>(2 * k, 3) = pj.d_point;
    }
    if (!ok) continue;
    // (I - H) J_theta, H = J_p (J_p^T J_p)^-1 J_p^T.
    const Eigen::MatrixXd absorbed =
        j_pose * (j_pose.transpose() * j_pose).ldlt().solve(j_pose.transpose() * j_theta);
    const Eigen::MatrixXd left = j_theta - absorbed;
    const double calibration_part =
        refit_factor * (left * fit.covariance * left.transpose()).trace();
    const double noise_part = noise_var * (2 * n - 6);
    const double per_coordinate = held.rms_reproj_px / std::sqrt(2.0);
    rms.push_back(per_coordinate);
    formal_ratio.push_back(per_coordinate / std::sqrt((noise_part + calibration_part) / (2 * n)));
    quoted_ratio.push_back(
        per_coordinate /
        std::sqrt((noise_part + u->scale * u->scale * calibration_part) / (2 * n)));
    excess_sum += held.rms_reproj_px * held.rms_reproj_px * n - noise_part;
    calibration_sum += calibration_part;
  }
  u->held_out_excess_ratio = calibration_sum > 0
                                 ? std::sqrt(std::max(0.0, excess_sum) / calibration_sum)
                                 : std::numeric_limits<double>::quiet_NaN();
  u->held_out_views = static_cast<int>(rms.size());
  u->held_out_rms_px = Median(rms);
  u->held_out_formal_ratio = Median(formal_ratio);
  u->held_out_quoted_ratio = Median(quoted_ratio);
}

}  // namespace

std::optional<CalibrationUncertainty> AssessProjectionUncertainty(
    const std::vector<View>& views, const RefineOptions& refine, const RefineResult& fit,
    const std::optional<JackknifeResult>& jackknife, int image_width, int image_height,
    const CalibrationUncertaintyOptions& options) {
  if (!fit.IsUsable() || !fit.projection.IsSet() || image_width <= 0 || image_height <= 0) {
    return std::nullopt;
  }
  CalibrationUncertainty u;
  u.distance_m = options.distance_m;
  UncertaintyMapOptions map_options;
  map_options.cols = options.grid_cols;
  map_options.distance_m = options.distance_m;
  u.formal = ProjectionUncertaintyMap(fit.intrinsics, fit.projection, image_width, image_height,
                                      map_options);
  if (jackknife)
    u.jackknife = JackknifeMap(fit, *jackknife, u.formal.worst_std_px, options.distance_m);
  if (u.jackknife) {
    std::vector<double> ratios;
    const std::vector<double>& f = u.formal.worst_std_px.values;
    const std::vector<double>& jk = u.jackknife->worst_std_px.values;
    for (size_t s = 0; s < f.size(); ++s) {
      if (std::isfinite(f[s]) && std::isfinite(jk[s]) && f[s] > 0) ratios.push_back(jk[s] / f[s]);
    }
    if (!ratios.empty()) {
      std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
      u.jackknife_ratio = ratios[ratios.size() / 2];
      u.scale = std::max(1.0, u.jackknife_ratio);
    }
  }
  u.quoted = fit.projection;
  u.quoted.covariance *= u.scale * u.scale;
  u.quoted.sigma_px *= u.scale;
  u.quoted_map = u.formal;
  for (double& v : u.quoted_map.worst_std_px.values) v *= u.scale;
  SummariseUncertaintyMap(&u.quoted_map);
  if (u.jackknife && views.size() == jackknife->leave_one_out.size()) {
    HeldOutViews(views, refine, fit, *jackknife, &u);
  }
  return u;
}

std::string FormatProjectionUncertainty(const CalibrationUncertainty& u) {
  char line[1024];
  const std::string at = std::isinf(u.distance_m)
                             ? std::string("rays at infinity")
                             : "points at " + std::to_string(u.distance_m).substr(0, 4) + " m";
  const std::string region = WorstRegion(u.quoted_map.worst_std_px, nullptr);
  std::snprintf(line, sizeof(line),
                "Projection uncertainty (%s, worst direction, 1 sigma): centre %.3f px, median "
                "%.3f px, worst %.3f px (%s)%s\n",
                at.c_str(), u.quoted_map.centre_px, u.quoted_map.median_px, u.quoted_map.max_px,
                region.empty() ? "-" : region.c_str(),
                u.scale > 1.0 ? ", scaled by the jackknife" : "");
  std::string text = line;
  if (u.jackknife) {
    std::snprintf(line, sizeof(line),
                  "  formal (corner noise %.3f px, independent): median %.3f px; leave-one-view-"
                  "out: median %.3f px, %.2fx the formal%s\n",
                  u.quoted.sigma_px / u.scale, u.formal.median_px, u.jackknife->median_px,
                  u.jackknife_ratio,
                  u.jackknife_ratio > 1.5 ? " (corners of a view share their errors: the "
                                            "jackknife figure is quoted)"
                                          : "");
  } else {
    std::snprintf(line, sizeof(line),
                  "  formal only (corner noise %.3f px, assumed independent; no jackknife: real "
                  "corners usually make it 2-9x too small)\n",
                  u.quoted.sigma_px);
  }
  text += line;
  if (u.held_out_views > 0) {
    std::snprintf(line, sizeof(line),
                  "  held-out views: each view against the calibration without it, median error "
                  "%.3f px per coordinate = %.2fx the formal prediction (noise included); their "
                  "excess over the noise %.2fx the formal calibration part\n",
                  u.held_out_rms_px, u.held_out_formal_ratio, u.held_out_excess_ratio);
    text += line;
  }
  return text;
}

}  // namespace calibench
