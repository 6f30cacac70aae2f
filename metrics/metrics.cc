#include "metrics/metrics.h"

#include <cmath>
#include <limits>

#include "camera/image_grid.h"

namespace calibench {

Eigen::Vector3d RollPitchYawOfRc(const Eigen::Matrix3d& r_c, bool improper) {
  return RollPitchYawDeg(improper ? Eigen::Matrix3d(-r_c) : r_c);
}

double AngleDifferenceDeg(double a_deg, double b_deg) {
  double d = std::fmod(a_deg - b_deg, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d <= -180.0) d += 360.0;
  return d;
}

CameraErrors CameraErrorsAgainst(const CameraEstimate& e, const CameraSpec& truth) {
  CameraErrors errors;
  if (!e.has_camera) return errors;
  const CameraIntrinsics &k = e.intrinsics, &t = truth.intrinsics;
  errors.fku_px = k.fku_px - t.fku_px;
  errors.fkv_px = k.fkv_px - t.fkv_px;
  errors.phi_deg = k.phi_deg - t.phi_deg;
  errors.u0_px = k.u0_px - t.u0_px;
  errors.v0_px = k.v0_px - t.v0_px;
  const Eigen::Matrix3d& r_c = e.parent_from_cam.rotation;
  errors.rotation_deg = RotationAngleDeg(r_c, truth.r_c);
  const Eigen::Vector3d rpy = RollPitchYawOfRc(r_c, e.improper);
  const Eigen::Vector3d rpy_true = RollPitchYawOfRc(truth.r_c, truth.r_c.determinant() < 0);
  errors.roll_deg = AngleDifferenceDeg(rpy[0], rpy_true[0]);
  errors.pitch_deg = AngleDifferenceDeg(rpy[1], rpy_true[1]);
  errors.yaw_deg = AngleDifferenceDeg(rpy[2], rpy_true[2]);
  errors.position_m = (e.parent_from_cam.translation - truth.x_c).norm();
  return errors;
}

double ThetaError(const Vector16d& theta_true, const Vector16d& theta_hat) {
  const double scale_true = theta_true.segment<3>(8).norm();
  const double scale_hat = theta_hat.segment<3>(8).norm();
  if (!(scale_hat > 0) || !std::isfinite(scale_hat)) return std::numeric_limits<double>::infinity();
  const Vector16d truth = theta_true / scale_true;
  const double sign = theta_hat.segment<3>(8).dot(truth.segment<3>(8)) < 0 ? -1.0 : 1.0;
  return (truth - theta_hat / (sign * scale_hat)).norm();
}

Vector16d TrueTheta(const CameraSpec& truth) {
  return ThetaFromCamera(truth.intrinsics, truth.ParentFromCam().Inverse());
}

double ThetaErrorOf(const CameraEstimate& e, const CameraSpec& truth) {
  if (e.theta) return ThetaError(TrueTheta(truth), *e.theta);
  if (!e.has_camera) return kNoValue;
  return ThetaError(TrueTheta(truth), ThetaFromCamera(e.intrinsics, e.cam_from_parent));
}

double RmsReprojectionPx(const CameraEstimate& e, const std::vector<View>& views) {
  if (!e.theta && !e.has_camera) return kNoValue;
  const Matrix34d m = e.theta ? MFromTheta(*e.theta) : Matrix34d::Zero();
  double sum = 0.0;
  long count = 0;
  for (const View& view : views) {
    for (size_t i = 0; i < view.pixels.size(); ++i) {
      Eigen::Vector2d pixel;
      if (e.theta) {
        pixel = (m * view.points[i].homogeneous()).hnormalized();
      } else if (!ProjectPoint(e.intrinsics, e.cam_from_parent * view.points[i], &pixel)) {
        continue;
      }
      sum += (pixel - view.pixels[i]).squaredNorm();
      ++count;
    }
  }
  return count ? std::sqrt(sum / count) : kNoValue;
}

namespace {

// Whether `model` estimates lens terms beyond the pinhole's (the 11 x 11 covariance has none).
bool FreesDistortion(LensModel model) {
  for (const LensModelInfo& info : LensModels()) {
    if (info.model == model) return !info.free_distortion.empty();
  }
  return false;
}

}  // namespace

ProjectionError ProjectionErrorAgainst(const CameraEstimate& estimate, const CameraSpec& truth,
                                       int image_width, int image_height,
                                       const ProjectionErrorOptions& options) {
  ProjectionError out;
  if (!estimate.has_camera || image_width <= 0 || image_height <= 0) return out;
  const std::vector<Rigid3> true_pose = {truth.ParentFromCam().Inverse()};
  const std::vector<Rigid3> estimated_pose = {estimate.cam_from_parent};
  // The prediction: only from a complete covariance (no free distortion terms it would miss).
  // The estimate's own Cov(z) (every lens term), else its 11 x 11 mapped (pinhole models only).
  ProjectionCovariance predicted = estimate.projection;
  const bool predicts =
      predicted.IsSet() ||
      (!FreesDistortion(estimate.lens) &&
       ProjectionCovarianceOfEstimate(estimate.covariance, estimate.cam_from_parent, &predicted));
  const double infinity = std::numeric_limits<double>::infinity();
  const ImageGrid grid = ImageGrid::Over(image_width, image_height, options.cols);
  double sum_sq_err = 0.0, sum_sq_std = 0.0;
  int predicted_pixels = 0;
  for (int j = 0; j < grid.rows; ++j) {
    for (int i = 0; i < grid.cols; ++i) {
      const Eigen::Vector2d q = grid.PixelAt(i, j);
      Eigen::Vector2d reprojected;
      if (!ReprojectThroughEstimate(truth.intrinsics, estimate.intrinsics, true_pose,
                                    estimated_pose, q, infinity, &reprojected)) {
        continue;
      }
      sum_sq_err += (reprojected - q).squaredNorm();
      ++out.pixels;
      PixelUncertainty u;
      if (predicts &&
          ProjectionUncertaintyAt(estimate.intrinsics, predicted, q, infinity, &u, nullptr)) {
        // E|q' - q|^2 = trace of the 2 x 2 covariance: the sum of the ellipse's axes squared (the
        // worst direction alone would make a consistent method's ratio up to sqrt(2)).
        sum_sq_std += u.worst_std_px * u.worst_std_px + u.smallest_std_px * u.smallest_std_px;
        ++predicted_pixels;
      }
    }
  }
  if (out.pixels == 0) return out;
  out.rms_px = std::sqrt(sum_sq_err / out.pixels);
  // The ratio only where the prediction covers every pixel of the error.
  if (predicts && predicted_pixels == out.pixels && sum_sq_std > 0) {
    out.predicted_px = std::sqrt(sum_sq_std / predicted_pixels);
    out.ratio = out.rms_px / out.predicted_px;
  }
  return out;
}

EstimateMetrics EvaluateEstimate(MethodStatus status, const CameraEstimate& estimate,
                                 const CameraSpec& truth, int image_width, int image_height,
                                 const std::vector<View>& views) {
  EstimateMetrics m;
  m.projection = ProjectionErrorAgainst(estimate, truth, image_width, image_height, {});
  m.errors = CameraErrorsAgainst(estimate, truth);
  m.theta_err_norm = ThetaErrorOf(estimate, truth);
  if (std::isfinite(estimate.fit_rms_px)) {
    m.rms_reproj_px = estimate.fit_rms_px;
  } else if (status == MethodStatus::kOk) {
    m.rms_reproj_px = RmsReprojectionPx(estimate, views);
  }
  if (estimate.has_camera && estimate.improper && !truth.allow_improper_rotation) {
    m.warning = "recovered rotation is improper (det < 0)";
  }
  return m;
}

CrlbStd CramerRaoStd(const std::vector<View>& views, const CameraSpec& truth,
                     const Parametrisation& parametrisation, double pixel_sigma_px) {
  RefineOptions options;
  ApplyParametrisation(parametrisation, &options);
  CrlbStd bound;
  IntrinsicsCovariance cov;
  bound.valid = IntrinsicsCovarianceAt(views, truth.intrinsics, {truth.ParentFromCam().Inverse()},
                                       options, pixel_sigma_px, &cov, nullptr);
  if (!bound.valid) return bound;
  const double deg = 180.0 / M_PI;
  bound.std_px = {std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1)),
                  parametrisation.estimate_skew ? std::sqrt(cov(2, 2)) * deg : kNoValue,
                  std::sqrt(cov(3, 3)), std::sqrt(cov(4, 4))};
  return bound;
}

ThetaTrack::ThetaTrack(const CameraSpec& truth, const Options& options)
    : theta_true_(TrueTheta(truth)), options_(options) {}

void ThetaTrack::Add(double t_s, const Vector16d& theta_hat) {
  const double error = ThetaError(theta_true_, theta_hat);
  if (options_.record_curve) curve_.emplace_back(t_s, error);
  if (error >= options_.tolerance) {
    last_above_ = t_s;
    pending_ = true;
  } else if (pending_) {
    first_after_ = t_s;
    pending_ = false;
  }
}

double ThetaTrack::ConvergeTimeS() const {
  return pending_ ? kNoValue : (last_above_ < 0 ? 0.0 : first_after_);
}

std::vector<std::pair<double, double>> ThetaTrack::Curve() const {
  const int max_samples = options_.max_samples;
  if (max_samples < 2 || static_cast<int>(curve_.size()) <= max_samples) return curve_;
  std::vector<std::pair<double, double>> kept;
  kept.reserve(max_samples);
  const double stride = static_cast<double>(curve_.size() - 1) / (max_samples - 1);
  for (int i = 0; i < max_samples; ++i) {
    kept.push_back(curve_[static_cast<size_t>(std::lround(i * stride))]);
  }
  return kept;
}

}  // namespace calibench
