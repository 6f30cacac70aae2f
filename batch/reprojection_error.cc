#include "batch/reprojection_error.h"

namespace calibench {

bool ReprojectionCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  return EvaluatePoint(parameters, std::sin(parameters[0][2]), std::cos(parameters[0][2]),
                       point_in_object_, pixel_, residuals, jacobians);
}

ViewReprojectionCostFunction::ViewReprojectionCostFunction(std::vector<Eigen::Vector3d> points,
                                                           std::vector<Eigen::Vector2d> pixels)
    : points_(std::move(points)), pixels_(std::move(pixels)) {
  set_num_residuals(2 * static_cast<int>(points_.size()));
  *mutable_parameter_block_sizes() = {PinholeSkewCamera::kNumParams, 4, 3};
}

bool ViewReprojectionCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  constexpr int kSizes[3] = {PinholeSkewCamera::kNumParams, 4, 3};
  double* point_jacobians[3] = {nullptr, nullptr, nullptr};
  const double sin_phi = std::sin(parameters[0][2]), cos_phi = std::cos(parameters[0][2]);
  for (size_t i = 0; i < points_.size(); ++i) {
    if (jacobians != nullptr) {
      for (int b = 0; b < 3; ++b) {
        point_jacobians[b] = jacobians[b] ? jacobians[b] + 2 * i * kSizes[b] : nullptr;
      }
    }
    if (!ReprojectionCostFunction::EvaluatePoint(parameters, sin_phi, cos_phi, points_[i],
                                                 pixels_[i], residuals + 2 * i,
                                                 jacobians ? point_jacobians : nullptr)) {
      return false;
    }
  }
  return true;
}

bool ReprojectionCostFunction::EvaluatePoint(double const* const* parameters, double sin_phi,
                                             double cos_phi, const Eigen::Vector3d& point,
                                             const Eigen::Vector2d& pixel, double* residuals,
                                             double* const* jacobians) {
  const double* k = parameters[0];
  const double* q = parameters[1];  // x, y, z, w
  const double* t = parameters[2];
  const Eigen::Vector3d q_v(q[0], q[1], q[2]);
  const double w = q[3];
  const Eigen::Vector3d& p = point;
  // Eigen's unit-quaternion rotation: v + 2w (q_v x v) + 2 q_v x (q_v x v).
  const Eigen::Vector3d qxp = q_v.cross(p);
  const Eigen::Vector3d point_in_cam =
      p + 2.0 * w * qxp + 2.0 * q_v.cross(qxp) + Eigen::Vector3d(t[0], t[1], t[2]);
  if (!(point_in_cam.z() > 0)) return false;
  const double inv_z = 1.0 / point_in_cam.z();
  const double x = point_in_cam.x() * inv_z, y = point_in_cam.y() * inv_z;
  const double fku = k[0], fkv = k[1];
  const double k1 = k[5], k2 = k[6], p1 = k[7], p2 = k[8], k3 = k[9];
  const double r2 = x * x + y * y;
  const double d = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xy = x * y;
  const double xd = d * x + 2.0 * p1 * xy + p2 * (r2 + 2.0 * x * x);
  const double yd = d * y + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * xy;
  const double cot_phi = cos_phi / sin_phi;
  residuals[0] = fku * (xd - yd * cot_phi) + k[3] - pixel.x();
  residuals[1] = fkv * yd / sin_phi + k[4] - pixel.y();
  if (jacobians == nullptr) return true;

  // d(u, v)/d(xd, yd).
  Eigen::Matrix2d du_dd;
  du_dd << fku, -fku * cot_phi, 0.0, fkv / sin_phi;
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 10, Eigen::RowMajor>> j(jacobians[0]);
    j.setZero();
    j(0, 0) = xd - yd * cot_phi;
    j(1, 1) = yd / sin_phi;
    j(0, 2) = fku * yd / (sin_phi * sin_phi);
    j(1, 2) = -fkv * yd * cos_phi / (sin_phi * sin_phi);
    j(0, 3) = 1.0;
    j(1, 4) = 1.0;
    // d(xd, yd)/d(k1, k2, p1, p2, k3), then through du_dd.
    Eigen::Matrix<double, 2, 5> dd_dk;
    const double r4 = r2 * r2;
    dd_dk << x * r2, x * r4, 2.0 * xy, r2 + 2.0 * x * x, x * r4 * r2,  //
        y * r2, y * r4, r2 + 2.0 * y * y, 2.0 * xy, y * r4 * r2;
    const Eigen::Matrix<double, 2, 5> duv_dk = du_dd * dd_dk;
    j.block<2, 2>(0, 5) = duv_dk.leftCols<2>();
    j.block<2, 2>(0, 7) = duv_dk.block<2, 2>(0, 2);
    j.col(9) = duv_dk.col(4);
  }
  if (jacobians[1] == nullptr && jacobians[2] == nullptr) return true;
  // d(xd, yd)/d(x, y).
  const double dd_dr2 = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2);
  Eigen::Matrix2d dd_dn;
  dd_dn << d + 2.0 * x * x * dd_dr2 + 2.0 * p1 * y + 6.0 * p2 * x,
      2.0 * xy * dd_dr2 + 2.0 * p1 * x + 2.0 * p2 * y,
      2.0 * xy * dd_dr2 + 2.0 * p1 * x + 2.0 * p2 * y,
      d + 2.0 * y * y * dd_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
  // d(x, y)/d(point_in_cam).
  Eigen::Matrix<double, 2, 3> dn_dx;
  dn_dx << inv_z, 0.0, -x * inv_z, 0.0, inv_z, -y * inv_z;
  const Eigen::Matrix<double, 2, 3> duv_dx = du_dd * dd_dn * dn_dx;
  if (jacobians[2] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> j_translation(jacobians[2]);
    j_translation = duv_dx;
  }
  if (jacobians[1] != nullptr) {
    auto hat = [](const Eigen::Vector3d& a) {
      Eigen::Matrix3d h;
      h << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
      return h;
    };
    Eigen::Matrix<double, 3, 4> dx_dq;
    dx_dq.leftCols<3>() = -2.0 * w * hat(p) - 2.0 * hat(qxp) - 2.0 * hat(q_v) * hat(p);
    dx_dq.col(3) = 2.0 * qxp;
    Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>> j_rotation(jacobians[1]);
    j_rotation = duv_dx * dx_dq;
  }
  return true;
}

}  // namespace calibench
