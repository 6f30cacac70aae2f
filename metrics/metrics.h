// Every figure calibench reports about an estimate, computed in one place from the estimate
// (camera/estimate.h) plus the truth or the measurements. No method computes its own errors.
//
//   camera errors   estimate minus truth: f*ku, f*kv, phi, u0, v0; the extrinsic rotation as one
//                   geodesic angle, angle(R_C_hat R_C^T) after projecting onto SO(3), and per
//                   Euler angle (roll, pitch, yaw of R_C in the README's convention, camera/pose.h;
//                   an opted-in improper R_C is compared through -R_C, a proper rotation),
//                   wrapped to (-180, 180]; the position error |x_C_hat - x_C|.
//   ||theta~||      the thesis's error figure ||theta - theta_hat / lambda|| (spec "Recovering the
//                   parameters"): theta_hat scaled so that the third row of its 3x3 block has unit
//                   norm, with the sign that best matches theta (itself normalised). Distortion is
//                   not part of theta.
//   projection      the estimate's projection error against the truth over the image: at a grid of
//                   the truth's image (ProjectionErrorOptions), the ray the truth sees at pixel q
//                   is brought into the parent frame by the true pose, back by the estimate's and
//                   projected by the estimate (batch/projection_uncertainty.h
//                   ReprojectThroughEstimate); proj_err_px is the RMS of |q' - q| over the pixels
//                   where the truth unprojects. proj_err_ratio divides it by the RMS over the same
//                   pixels of the predicted |q' - q|, sqrt(trace) of the 2 x 2 projection
//                   covariance the estimate's own covariance predicts there
//                   (ProjectionCovarianceOfEstimate; the worst-direction std alone would put a
//                   consistent method anywhere in [1, sqrt 2]): ~1 when the method knows how wrong
//                   it is, >> 1 overconfident. NaN without a covariance, and for a lens model with
//                   free distortion terms (the 11 x 11 covariance has none: the prediction would
//                   miss them).
//   reprojection    per-point Euclidean RMS (px) of the estimate's projection (camera/estimate.h)
//                   against the measured pixels of the trial's frames.
//   CRLB            the Cramer-Rao standard deviations of the intrinsics for white pixel noise of
//                   std sigma: sigma^2 (J^T J)^-1 at the truth, poses marginalised
//                   (batch/refine.h), for the parametrisation a method estimates.
//   convergence     the first time after which ||theta~(t)|| stays below a tolerance, from an
//                   estimate's trajectory (ThetaTrack).
#pragma once

#include <array>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "batch/projection_uncertainty.h"
#include "batch/refine.h"
#include "camera/estimate.h"
#include "camera/parametrisation.h"
#include "camera/projection_matrix.h"
#include "camera/view.h"
#include "sim/scene.h"
#include "util/status.h"

namespace calibench {

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// Estimate minus truth (angles in degrees, pixels in px, the position in the scene's unit).
struct CameraErrors {
  double fku_px = kNoValue, fkv_px = kNoValue, phi_deg = kNoValue, u0_px = kNoValue,
         v0_px = kNoValue;
  double rotation_deg = kNoValue;  // Geodesic.
  double roll_deg = kNoValue, pitch_deg = kNoValue, yaw_deg = kNoValue;
  double position_m = kNoValue;  // |x_C_hat - x_C|.
};
CameraErrors CameraErrorsAgainst(const CameraEstimate& estimate, const CameraSpec& truth);

// Roll, pitch, yaw (degrees) of R_C, through -R_C when it is improper.
Eigen::Vector3d RollPitchYawOfRc(const Eigen::Matrix3d& r_c, bool improper);
// a - b wrapped to (-180, 180] degrees.
double AngleDifferenceDeg(double a_deg, double b_deg);

// The thesis error figure (see the header comment); infinity for a theta_hat whose third row is 0.
double ThetaError(const Vector16d& theta_true, const Vector16d& theta_hat);
// theta of the truth (its intrinsics' A and cam_from_parent; distortion is not part of theta).
Vector16d TrueTheta(const CameraSpec& truth);
// ||theta~|| of an estimate: its own theta, else its camera form's; NaN when it holds neither.
double ThetaErrorOf(const CameraEstimate& estimate, const CameraSpec& truth);

// Per-point RMS reprojection error (px) of the estimate over `views` (points in the parent frame,
// measured pixels); NaN when it projects nothing. A point that projects behind the camera counts
// as a missing point: RMS over the others.
double RmsReprojectionPx(const CameraEstimate& estimate, const std::vector<View>& views);

// The grid of the projection error (header comment).
struct ProjectionErrorOptions {
  int cols = 16;  // Grid columns across the truth's image; rows follow its aspect ratio.
};
struct ProjectionError {
  double rms_px = kNoValue;  // proj_err_px.
  double ratio = kNoValue;   // proj_err_ratio: rms_px / predicted_px.
  // RMS over the grid of the predicted |q' - q| (sqrt of the trace of the pixel covariance).
  double predicted_px = kNoValue;
  int pixels = 0;  // Grid pixels used (the truth unprojects, the estimate projects).
};
// NaN figures for an estimate without a camera, an image size that is not positive or a grid where
// no pixel reprojects.
ProjectionError ProjectionErrorAgainst(const CameraEstimate& estimate, const CameraSpec& truth,
                                       int image_width, int image_height,
                                       const ProjectionErrorOptions& options);

// The figures of one method's result against the truth and the trial's frames.
struct EstimateMetrics {
  CameraErrors errors;  // When the estimate has a camera.
  double theta_err_norm = kNoValue;
  double rms_reproj_px = kNoValue;  // Of an ok result; the method's own fit_rms_px if set.
  ProjectionError projection;       // Of an estimate with a camera, over the truth's image.
  // A finding the row must carry, e.g. a reflection estimated for a proper camera.
  std::string warning;
};
// image_width, image_height: the truth camera's image (px), for the projection error.
EstimateMetrics EvaluateEstimate(MethodStatus status, const CameraEstimate& estimate,
                                 const CameraSpec& truth, int image_width, int image_height,
                                 const std::vector<View>& views);

// Cramer-Rao standard deviations of f*ku, f*kv, phi (deg; NaN without skew), u0, v0 (px).
struct CrlbStd {
  bool valid = false;  // False when J^T J is rank deficient.
  std::array<double, 5> std_px{kNoValue, kNoValue, kNoValue, kNoValue, kNoValue};
};
// `views`: exact points in the parent frame (pixels are not used: J does not involve them);
// `parametrisation`: what the estimator frees (lens model, skew; a shared pose).
CrlbStd CramerRaoStd(const std::vector<View>& views, const CameraSpec& truth,
                     const Parametrisation& parametrisation, double pixel_sigma_px);

// ||theta~(t)|| along an estimate's trajectory: the convergence time and, when recording, the
// curve (thinned to at most max_samples evenly spaced samples, always keeping the last).
class ThetaTrack {
 public:
  struct Options {
    double tolerance = 1e-4;  // converge_time_s: first t after which ||theta~|| < this.
    bool record_curve = false;
    int max_samples = 300;
  };
  ThetaTrack(const CameraSpec& truth, const Options& options);
  void Add(double t_s, const Vector16d& theta_hat);
  // The first recorded t after the last one with ||theta~|| >= tolerance (0 if never above);
  // NaN if the last recorded value is still above it.
  double ConvergeTimeS() const;
  std::vector<std::pair<double, double>> Curve() const;

 private:
  Vector16d theta_true_;
  Options options_;
  double last_above_ = -1.0, first_after_ = 0.0;
  bool pending_ = false;
  std::vector<std::pair<double, double>> curve_;
};

}  // namespace calibench
