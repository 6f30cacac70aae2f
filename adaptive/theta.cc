#include "adaptive/theta.h"

#include <cmath>
#include <sstream>

namespace calibench {

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

double ThetaError(const Vector16d& theta_true, const Vector16d& theta_hat) {
  const double scale_true = theta_true.segment<3>(8).norm();
  const double scale_hat = theta_hat.segment<3>(8).norm();
  if (!(scale_hat > 0) || !std::isfinite(scale_hat)) return std::numeric_limits<double>::infinity();
  const Vector16d truth = theta_true / scale_true;
  const double sign = theta_hat.segment<3>(8).dot(truth.segment<3>(8)) < 0 ? -1.0 : 1.0;
  return (truth - theta_hat / (sign * scale_hat)).norm();
}

bool RecoverCamera(const Vector16d& theta_hat, const std::vector<Eigen::Vector3d>& points_in_parent,
                   RecoveredCamera* camera, std::string* why) {
  if (!theta_hat.allFinite()) {
    if (why) *why = "theta_hat has non-finite entries";
    return false;
  }
  return DecomposeProjectionMatrix(MFromTheta(theta_hat), points_in_parent, camera, why);
}

}  // namespace calibench
