// Decomposition of a 3x4 projection matrix M ~ A [R | t] (known only up to scale, sign included)
// into intrinsics with skew, rotation and translation. Used by the adaptive estimator (its theta
// is M row by row) and by the DLT.
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

#include "core/camera.h"
#include "core/pose.h"

namespace calibench {

using Matrix34d = Eigen::Matrix<double, 3, 4>;

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

}  // namespace calibench
