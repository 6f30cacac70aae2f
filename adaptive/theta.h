// The linear parametrisation of the thesis (spec "Linear parametrisation") and the recovery of
// the calibration parameters from an estimate (spec "Recovering the parameters", appendix A.2).
//
//   M = A [R | t] in R^{3x4};  theta_x = rows of M, row after row (12);  theta_z = row 3 of M (4);
//   theta = [theta_x; theta_z] in R^16.
//   Per point: x_bar = [x y z 1]^T, W_x = blockdiag(x_bar^T, x_bar^T, x_bar^T) (3x12),
//   W_z = x_bar^T (1x4):  W_x theta_x = M x_bar,  W_z theta_z = depth z.
//
// Recovery from theta_hat: D = left 3x3 of M_hat, d = column 4; K = D D^T; lambda = +-sqrt(K33)
// with the sign that puts the points in front of the camera (depth M_hat_3 x_bar / lambda > 0);
// D, d /= lambda; K /= K33; a3 = K13, a5 = K23, a4 = sqrt(K22 - a5^2), a2 = (K12 - a3 a5)/a4,
// a1 = sqrt(K11 - a2^2 - a3^2); R = A^-1 D, t = A^-1 d; R_C = R^T, x_C = -R_C t.
// R is orthonormal only when theta_hat is exact: its defect ||R^T R - I||_F is reported and the
// reported R_C is the nearest orthogonal matrix of the same handedness (det sign of D).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/pose.h"

namespace calibench {

using Vector16d = Eigen::Matrix<double, 16, 1>;
using Matrix16d = Eigen::Matrix<double, 16, 16>;
using Matrix34d = Eigen::Matrix<double, 3, 4>;

Vector16d ThetaFromM(const Matrix34d& m);
// M from theta_x (the first 12 entries); theta_z is not used.
Matrix34d MFromTheta(const Vector16d& theta);
// theta of a camera: M = A [R | t] with cam_from_parent = {R, t}. A has a33 = 1, so for a proper
// R the third row of D already has unit norm: the thesis's normalisation.
Vector16d ThetaFromCamera(const CameraIntrinsics& intrinsics, const Rigid3& cam_from_parent);

// The thesis error figure ||theta - theta_hat / lambda||: theta_hat is scaled so that the third
// row of its D has unit norm, with the sign that best matches theta_true (itself normalised).
double ThetaError(const Vector16d& theta_true, const Vector16d& theta_hat);

struct RecoveredCamera {
  CameraIntrinsics intrinsics;        // Distortion is zero: M carries none.
  Rigid3 parent_from_cam;             // {R_C, x_C}; R_C orthogonalised (same handedness).
  Eigen::Matrix3d raw_rotation;       // R = A^-1 D before orthogonalisation (cam_from_parent).
  double orthogonality_defect = 0.0;  // ||R^T R - I||_F of raw_rotation.
  bool improper = false;              // det(R) < 0: a reflection.
  double lambda = 0.0;                // Signed scale removed from theta_hat.
};

// Recovers the camera from theta_hat. `points_in_parent` (x_bar without the 1) fix the sign of the
// scale by cheirality (majority of positive depths). Returns false with a reason when M is
// degenerate (K not positive definite, non-finite entries).
bool RecoverCamera(const Vector16d& theta_hat, const std::vector<Eigen::Vector3d>& points_in_parent,
                   RecoveredCamera* camera, std::string* why);

}  // namespace calibench
