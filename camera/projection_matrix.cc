#include "camera/projection_matrix.h"

#include <cmath>

namespace calibench {

bool DecomposeProjectionMatrix(const Matrix34d& m,
                               const std::vector<Eigen::Vector3d>& points_in_parent,
                               DecomposedCamera* camera, std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (!m.allFinite()) return fail("M has non-finite entries");
  Eigen::Matrix3d d_mat = m.leftCols<3>();
  Eigen::Vector3d d_vec = m.col(3);
  const Eigen::Matrix3d k_raw = d_mat * d_mat.transpose();
  if (!(k_raw(2, 2) > 0)) return fail("third row of M is zero: no depth information");

  // Cheirality: the sign of lambda that makes most depths positive.
  int positive = 0;
  for (const Eigen::Vector3d& x : points_in_parent) {
    if (m.row(2).dot(x.homogeneous()) > 0) ++positive;
  }
  const double sign = 2 * positive >= static_cast<int>(points_in_parent.size()) ? 1.0 : -1.0;
  const double lambda = sign * std::sqrt(k_raw(2, 2));
  d_mat /= lambda;
  d_vec /= lambda;
  const Eigen::Matrix3d k = k_raw / k_raw(2, 2);

  const double a3 = k(0, 2), a5 = k(1, 2);
  const double a4_sq = k(1, 1) - a5 * a5;
  if (!(a4_sq > 0)) return fail("M is degenerate: K22 - a5^2 <= 0");
  const double a4 = std::sqrt(a4_sq);
  const double a2 = (k(1, 0) - a3 * a5) / a4;
  const double a1_sq = k(0, 0) - a2 * a2 - a3 * a3;
  if (!(a1_sq > 0)) return fail("M is degenerate: K11 - a2^2 - a3^2 <= 0");
  const double a1 = std::sqrt(a1_sq);

  Eigen::Matrix3d a;
  a << a1, a2, a3, 0, a4, a5, 0, 0, 1;
  const Eigen::Matrix3d a_inv = a.inverse();
  const Eigen::Matrix3d r = a_inv * d_mat;
  const Eigen::Vector3d t = a_inv * d_vec;

  camera->intrinsics = CameraIntrinsics::FromMatrix(a);
  camera->raw_rotation = r;
  camera->orthogonality_defect = OrthogonalityDefect(r);
  camera->improper = r.determinant() < 0;
  camera->lambda = lambda;
  const Eigen::Matrix3d r_c = r.transpose();
  // x_C from the raw R_C, as the thesis computes it; the reported R_C is orthogonalised.
  camera->parent_from_cam.translation = -(r_c * t);
  camera->parent_from_cam.rotation =
      camera->improper ? Eigen::Matrix3d(-ProjectToSO3(-r_c)) : ProjectToSO3(r_c);
  return true;
}

Vector16d ThetaFromM(const Matrix34d& m) {
  Vector16d theta;
  for (int r = 0; r < 3; ++r) theta.segment<4>(4 * r) = m.row(r).transpose();
  theta.segment<4>(12) = m.row(2).transpose();
  return theta;
}

Matrix34d MFromTheta(const Vector16d& theta) {
  Matrix34d m;
  for (int r = 0; r < 3; ++r) m.row(r) = theta.segment<4>(4 * r).transpose();
  return m;
}

Vector16d ThetaFromCamera(const CameraIntrinsics& intrinsics, const Rigid3& cam_from_parent) {
  return ThetaFromM(intrinsics.Matrix() * cam_from_parent.Matrix3x4());
}

bool RecoverCamera(const Vector16d& theta_hat, const std::vector<Eigen::Vector3d>& points_in_parent,
                   DecomposedCamera* camera, std::string* why) {
  if (!theta_hat.allFinite()) {
    if (why) *why = "theta_hat has non-finite entries";
    return false;
  }
  return DecomposeProjectionMatrix(MFromTheta(theta_hat), points_in_parent, camera, why);
}

}  // namespace calibench
