// The linear parametrisation of the thesis (spec "Linear parametrisation") and the recovery of
// the calibration parameters from an estimate (spec "Recovering the parameters", appendix A.2).
//
//   M = A [R | t] in R^{3x4};  theta_x = rows of M, row after row (12);  theta_z = row 3 of M (4);
//   theta = [theta_x; theta_z] in R^16.
//   Per point: x_bar = [x y z 1]^T, W_x = blockdiag(x_bar^T, x_bar^T, x_bar^T) (3x12),
//   W_z = x_bar^T (1x4):  W_x theta_x = M x_bar,  W_z theta_z = depth z.
//
// Recovery from theta_hat: M = MFromTheta(theta_hat), decomposed by core/projection_matrix.h.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/pose.h"
#include "core/projection_matrix.h"

namespace calibench {

using Vector16d = Eigen::Matrix<double, 16, 1>;
using Matrix16d = Eigen::Matrix<double, 16, 16>;

Vector16d ThetaFromM(const Matrix34d& m);
// M from theta_x (the first 12 entries); theta_z is not used.
Matrix34d MFromTheta(const Vector16d& theta);
// theta of a camera: M = A [R | t] with cam_from_parent = {R, t}. A has a33 = 1, so for a proper
// R the third row of D already has unit norm: the thesis's normalisation.
Vector16d ThetaFromCamera(const CameraIntrinsics& intrinsics, const Rigid3& cam_from_parent);

// The thesis error figure ||theta - theta_hat / lambda||: theta_hat is scaled so that the third
// row of its D has unit norm, with the sign that best matches theta_true (itself normalised).
double ThetaError(const Vector16d& theta_true, const Vector16d& theta_hat);

using RecoveredCamera = DecomposedCamera;

// Recovers the camera from theta_hat. `points_in_parent` (x_bar without the 1) fix the sign of the
// scale by cheirality (majority of positive depths). Returns false with a reason when M is
// degenerate (K not positive definite, non-finite entries).
bool RecoverCamera(const Vector16d& theta_hat, const std::vector<Eigen::Vector3d>& points_in_parent,
                   RecoveredCamera* camera, std::string* why);

}  // namespace calibench
