// Maximum-likelihood calibration refinement with Ceres (the `ceres` method), and the covariance /
// Cramer-Rao machinery that goes with it.
//
// Minimises sum over views v and points i of rho(|Project(A, cam_from_object_v * X_vi) - p_vi|^2)
// over the free intrinsics (lens model and skew choose them) and the poses. Two pose layouts:
//   per-view poses (shared_pose = false): classic camera calibration from a planar target;
//   one shared pose (shared_pose = true): a scenario's constant extrinsic, the points already
//       expressed in the parent frame P (x_bar) through the known body motion.
//
// Every lens family of camera/camera.h is refined, with the hand-written Jacobians of
// batch/projection_jacobian.h (autodiff: the ceres::Jet reference). The omnidirectional families'
// ranges are Ceres bounds on the intrinsics block: unified xi >= 0; eucm alpha in [0, 1], beta > 0;
// double sphere xi > -1, alpha in [0, 1] (a parameter that ends on a bound is reported there).
//
// Covariance of the intrinsics: sigma^2 (J^T J)^-1 restricted to the intrinsics, where sigma is
// the known pixel noise if given, else sigma_hat^2 = 2 cost / (m - p) (m residuals, p free
// parameters). Per-view poses: the Schur complement of the poses in J^T J (refine.cc,
// PerViewIntrinsicsCovariance); autodiff and IntrinsicsCovarianceAt: ceres::Covariance's dense
// SVD of the whole Jacobian (the same matrix, 10-50x slower; IntrinsicsCovarianceAt of one shared
// pose with normal_equations or over 200k residuals: the normal equations). Evaluated at the true
// parameters with the true sigma, the same computation is the Cramer-Rao lower bound
// (IntrinsicsCovarianceAt).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "batch/projection_uncertainty.h"
#include "camera/camera.h"
#include "camera/parametrisation.h"
#include "camera/pose.h"
#include "camera/view.h"
#include "util/status.h"

namespace calibench {

using IntrinsicsCovariance =
    Eigen::Matrix<double, PinholeSkewCamera::kNumParams, PinholeSkewCamera::kNumParams>;

// The robust loss on each point's reprojection residual (ceres::HuberLoss, ceres::CauchyLoss).
enum class RobustLoss { kNone, kHuber, kCauchy };
// Each loss with its name in configs ("none", "huber", "cauchy"), in declaration order.
const std::vector<std::pair<RobustLoss, const char*>>& RobustLossNames();

struct RefineOptions {
  LensModel model = LensModel::kPinhole;
  bool estimate_skew = true;  // Estimate phi; false fixes phi = 90 degrees.
  bool shared_pose = false;   // One cam_from_object for every view (see header comment).
  RobustLoss loss = RobustLoss::kNone;
  double loss_scale_px = 1.0;  // Scale of the robust loss.
  int max_iterations = 200;
  bool compute_covariance = true;
  // With shared_pose: also the joint covariance of the intrinsics and the pose
  // (RefineResult::joint_covariance) and RefineResult::projection. With normal_equations the
  // reported intrinsics covariance is its corner; without, ceres::Covariance's (the reference).
  bool compute_pose_covariance = false;
  double known_pixel_sigma_px =
      0.0;                // > 0: scale the covariance by it; 0: estimate from residuals.
  bool autodiff = false;  // true: ceres::Jet residual (the reference); false: analytic Jacobians.
  // The shared-pose problem's linear solver: false, dense QR of the Jacobian (the static rows'
  // reference); true, Cholesky of the normal equations J^T J, equal to ~1e-10 relative and ~1.5x
  // faster on the long windows of online mode (a growing window reaches 1e6 residuals).
  bool normal_equations = false;
  // Keep every intrinsic at its initial value and move only the poses: evaluates a given
  // calibration on new views (view_rms_px, rms_reproj_px); no covariance.
  bool fix_intrinsics = false;
  // Raw indices (0..9) kept at their initial value besides those the model fixes (a staged fit,
  // e.g. the wide start's focal length and centre before the lens terms: batch/wide_init.h).
  std::vector<int> extra_fixed_intrinsics;
  // The views' names in messages (e.g. their files); empty: "view <index>".
  std::vector<std::string> view_names;
  bool Check(std::string* why) const;
};

// The parametrisation (camera/parametrisation.h) a refinement with `options` estimates, and the
// options for one.
inline Parametrisation ParametrisationOf(const RefineOptions& options) {
  Parametrisation p;
  p.model = options.model;
  p.estimate_skew = options.estimate_skew;
  p.shared_pose = options.shared_pose;
  p.autodiff = options.autodiff;
  return p;
}
inline void ApplyParametrisation(const Parametrisation& p, RefineOptions* options) {
  options->model = p.model;
  options->estimate_skew = p.estimate_skew;
  options->shared_pose = p.shared_pose;
  options->autodiff = p.autodiff;
}

struct RefineResult : MethodSummary {
  CameraIntrinsics intrinsics;
  std::vector<Rigid3> cam_from_object;  // One per view, or one when shared_pose.
  IntrinsicsArray intrinsics_std{};     // NaN where fixed or not computed; phi in radians.
  IntrinsicsCovariance covariance = IntrinsicsCovariance::Zero();
  // compute_pose_covariance: 16 x 16 over [intrinsics (10, raw order; fixed ones 0), rotation (3,
  // the tangent d of cam_from_object's quaternion in ceres::EigenQuaternionManifold: R' =
  // Exp(2 d) R), translation (3)], scaled as
  // `covariance`. Empty otherwise.
  Eigen::MatrixXd joint_covariance;
  // Cov(z) of batch/projection_uncertainty.h, for the projection uncertainty: computed with the
  // covariance when the poses are per view, and with compute_pose_covariance for a shared pose.
  ProjectionCovariance projection;
  double rms_reproj_px = 0.0;  // Per-point Euclidean RMS.
  std::vector<double> view_rms_px;
  double sigma_hat_px = 0.0;  // Residual-based noise estimate (per coordinate).
  int num_points = 0;
  // When the solve fails: the view (index into `views`) the failure is traced to, named in
  // `message` (options.view_names, else "view N"): the first with a point that does not project
  // at the start (behind the camera or outside the lens's region: Ceres cannot evaluate it), else
  // the one farthest from the start (largest RMS). -1 when the solve succeeded.
  int failed_view = -1;
};

// `initial_poses` holds one pose per view, or one pose when options.shared_pose. Intrinsics the
// model does not estimate are reset to their neutral values (zero distortion, phi = 90 deg).
RefineResult RefineCalibration(const std::vector<View>& views, const CameraIntrinsics& initial,
                               const std::vector<Rigid3>& initial_poses,
                               const RefineOptions& options);

// camera/estimate.h's 11 x 11 covariance over [fku, fkv, phi_rad, u0, v0, dtheta (3, rad), x_C
// (3)] of a shared-pose refinement, from its joint_covariance over [intrinsics (10), rotation
// tangent (3), translation (3)] of cam_from_parent = {R, t}. Ceres' EigenQuaternionManifold moves
// the quaternion by [sin|d| d/|d|, cos|d|] * q: R' = Exp(2 d) R, so R_C' = R_C Exp(-2 d) =
// Exp(-2 R_C d) R_C, dtheta = -2 R^T d; x_C = -R^T t gives dx_C = -R^T dt - 2 R^T [t]x d.
// Empty when joint_covariance is not 16 x 16.
Eigen::MatrixXd EstimateCovarianceOfSharedPose(const Eigen::MatrixXd& joint_covariance,
                                               const Rigid3& cam_from_parent);

// sigma^2 (J^T J)^-1 for the free intrinsics at the given parameters (poses are nuisance
// parameters, marginalised). At the truth this is the CRLB. Returns false if J is rank deficient.
bool IntrinsicsCovarianceAt(const std::vector<View>& views, const CameraIntrinsics& intrinsics,
                            const std::vector<Rigid3>& poses, const RefineOptions& options,
                            double pixel_sigma_px, IntrinsicsCovariance* covariance,
                            std::string* why);

}  // namespace calibench
