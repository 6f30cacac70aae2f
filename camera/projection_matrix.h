// A 3x4 projection matrix M ~ A [R | t] (known only up to scale, sign included): the thesis's
// linear parametrisation theta of it, and its decomposition into intrinsics with skew, rotation
// and translation. Used by the adaptive estimator (its state is theta), the DLT and the metrics.
//
// Linear parametrisation (spec "Linear parametrisation"):
//   theta_x = rows of M, row after row (12);  theta_z = row 3 of M again (4);
//   theta = [theta_x; theta_z] in R^16.
//   Per point: x_bar = [x y z 1]^T, W_x = blockdiag(x_bar^T, x_bar^T, x_bar^T) (3x12),
//   W_z = x_bar^T (1x4):  W_x theta_x = M x_bar,  W_z theta_z = depth z.
// The adaptive estimator estimates theta_z separately, so its theta_hat_z need not equal row 3.
//
// Math (thesis appendix A.2; spec "Recovering the parameters"): D = left 3x3 of M, d = column 4;
// K = D D^T; lambda = +-sqrt(K33), with the sign that puts the points in front of the camera
// (depth M_3 x_bar / lambda > 0, majority vote); D, d /= lambda; K /= K33; then A A^T = K gives
// a3 = K13, a5 = K23, a4 = sqrt(K22 - a5^2), a2 = (K12 - a3 a5)/a4, a1 = sqrt(K11 - a2^2 - a3^2);
// R = A^-1 D, t = A^-1 d. R is orthonormal only for an exact M: its defect ||R^T R - I||_F is
// reported, and `parent_from_cam` carries the nearest orthogonal matrix of the same handedness.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/pose.h"

namespace calibench {

using Matrix34d = Eigen::Matrix<double, 3, 4>;
using Vector16d = Eigen::Matrix<double, 16, 1>;
using Matrix16d = Eigen::Matrix<double, 16, 16>;

Vector16d ThetaFromM(const Matrix34d& m);
// M from theta_x (the first 12 entries); theta_z is not used.
Matrix34d MFromTheta(const Vector16d& theta);
// theta of a camera: M = A [R | t] with cam_from_parent = {R, t} (distortion is not part of M).
// A has a33 = 1, so for a proper R the third row of D already has unit norm: the thesis's
// normalisation.
Vector16d ThetaFromCamera(const CameraIntrinsics& intrinsics, const Rigid3& cam_from_parent);

struct DecomposedCamera {
  CameraIntrinsics intrinsics;        // Distortion zero: M carries none.
  Rigid3 parent_from_cam;             // {R_C, x_C}; R_C orthogonalised (same handedness).
  Eigen::Matrix3d raw_rotation;       // R = A^-1 D before orthogonalisation (cam_from_parent).
  double orthogonality_defect = 0.0;  // ||R^T R - I||_F of raw_rotation.
  bool improper = false;              // det(R) < 0: a reflection.
  double lambda = 0.0;                // Signed scale removed from M.
};

// `points_in_parent` fix the sign of the scale by cheirality. Returns false with a reason when M
// is degenerate (K not positive definite, non-finite entries).
bool DecomposeProjectionMatrix(const Matrix34d& m,
                               const std::vector<Eigen::Vector3d>& points_in_parent,
                               DecomposedCamera* camera, std::string* why);

// DecomposeProjectionMatrix(MFromTheta(theta_hat)), refusing a non-finite theta_hat.
bool RecoverCamera(const Vector16d& theta_hat, const std::vector<Eigen::Vector3d>& points_in_parent,
                   DecomposedCamera* camera, std::string* why);

}  // namespace calibench
