// A calibration estimate as every method reports it (methods/method.h) and as the metrics compare
// it with the truth (metrics/). Value type; what a method does not estimate stays unset.
//
// An estimate holds the camera (intrinsics with its lens model's coefficients, and the extrinsic
// parent_from_cam = {R_C, x_C}, camera/pose.h), and says how it projects a point x of the parent
// frame, in the method's own parametrisation:
//   theta set   the thesis's theta (camera/projection_matrix.h) of a method that estimates
//               M = A [R | t] linearly (adaptive, dlt): pixel = (M x_bar) / (M_3 x_bar), M from
//               theta_x; its ||theta~|| uses all 16 entries (the adaptive estimator's theta_z is
//               its own);
//   otherwise   Project(intrinsics, cam_from_parent * x): the camera form (ceres, zhang), with
//               cam_from_parent the method's own solution (not re-derived from parent_from_cam, so
//               that no rounding is added to it).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>

#include "camera/camera.h"
#include "camera/pose.h"
#include "camera/projection_covariance.h"
#include "camera/projection_matrix.h"

namespace calibench {

struct CameraEstimate {
  // intrinsics, lens, parent_from_cam, cam_from_parent, improper and orthogonality_defect hold an
  // estimate. False for a method that failed, or that ended with theta only (a diverged run).
  bool has_camera = false;
  CameraIntrinsics intrinsics;  // f*ku, f*kv, phi, u0, v0 and the lens model's coefficients.
  LensModel lens = LensModel::kPinhole;
  Rigid3 parent_from_cam;             // R_C orthonormal (of the estimated handedness), x_C.
  Rigid3 cam_from_parent;             // The camera form's projection pose (see above).
  bool improper = false;              // The estimated rotation is a reflection (det < 0).
  double orthogonality_defect = 0.0;  // ||R^T R - I||_F before orthonormalisation (linear forms).
  std::optional<Vector16d> theta;     // The linear form (see above); may exist without a camera.
  // Cov(z) of the projection (camera/projection_covariance.h) with every lens term, when the
  // method computes it (ceres with one shared pose); unset otherwise (the metrics then map
  // `covariance`, which has no lens terms).
  ProjectionCovariance projection;

  // Reported standard deviations of the intrinsics (raw-array order, phi in radians); NaN where the
  // method reports none.
  IntrinsicsArray intrinsics_std = NaNs();
  // The covariance of the estimate, when the method reports one (empty otherwise): 11 x 11 over
  //   [fku_px, fkv_px, phi_rad, u0_px, v0_px, dtheta (3, rad), x_C (3, m)],
  // where dtheta is the rotation error in the parent frame, R_C_true = Exp(dtheta) R_C_hat. A
  // parameter the method does not estimate has zero variance.
  Eigen::MatrixXd covariance;
  static constexpr int kCovarianceSize = 11;
  // The method's own reprojection RMS (px, per point) where its model has more freedom than this
  // estimate (zhang: one board pose per view); NaN: the metrics reproject the estimate itself.
  double fit_rms_px = std::numeric_limits<double>::quiet_NaN();

  static IntrinsicsArray NaNs() {
    IntrinsicsArray a;
    a.fill(std::numeric_limits<double>::quiet_NaN());
    return a;
  }
};

}  // namespace calibench
