#include "batch/rig_reprojection_error.h"

#include "batch/projection_jacobian.h"
#include "camera/pose.h"

namespace calibench {
namespace {

constexpr int kBlockSizes[5] = {PinholeSkewCamera::kNumParams, 4, 3, 4, 3};

// q * p for a unit quaternion (x, y, z, w), Eigen's formula v + 2w (q_v x v) + 2 q_v x (q_v x v),
// and with `d_q` its 3 x 4 derivative in (x, y, z, w).
Eigen::Vector3d Rotate(const double* q, const Eigen::Vector3d& p,
                       Eigen::Matrix<double, 3, 4>* d_q) {
  const Eigen::Vector3d q_v(q[0], q[1], q[2]);
  const double w = q[3];
  const Eigen::Vector3d qxp = q_v.cross(p);
  if (d_q != nullptr) {
    d_q->leftCols<3>() = -2.0 * w * Hat(p) - 2.0 * Hat(qxp) - 2.0 * Hat(q_v) * Hat(p);
    d_q->col(3) = 2.0 * qxp;
  }
  return p + 2.0 * w * qxp + 2.0 * q_v.cross(qxp);
}

}  // namespace

RigViewCostFunction::RigViewCostFunction(std::vector<Eigen::Vector3d> points_in_board,
                                         std::vector<Eigen::Vector2d> pixels, LensFamily family)
    : points_(std::move(points_in_board)), pixels_(std::move(pixels)), family_(family) {
  set_num_residuals(2 * static_cast<int>(points_.size()));
  *mutable_parameter_block_sizes() = {kBlockSizes[0], kBlockSizes[1], kBlockSizes[2],
                                      kBlockSizes[3], kBlockSizes[4]};
}

bool RigViewCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  const double* intrinsics = parameters[0];
  const double* q_c = parameters[1];
  const Eigen::Vector3d t_c(parameters[2][0], parameters[2][1], parameters[2][2]);
  const double* q_f = parameters[3];
  const Eigen::Vector3d t_f(parameters[4][0], parameters[4][1], parameters[4][2]);
  const PinholeStep pinhole(intrinsics);
  const LensStepFunction lens = LensStepOf(family_);
  bool want[5] = {false, false, false, false, false};
  bool any = false;
  if (jacobians != nullptr) {
    for (int b = 0; b < 5; ++b) any |= want[b] = jacobians[b] != nullptr;
  }
  // R_c as a matrix for dP/dt_f and dP/dq_f (unit q_c, as Rotate assumes).
  Eigen::Matrix3d r_c;
  if (want[3] || want[4]) {
    for (int k = 0; k < 3; ++k) r_c.col(k) = Rotate(q_c, Eigen::Vector3d::Unit(k), nullptr);
  }
  Eigen::Matrix<double, 3, 4> d_qf, d_qc;
  for (size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d point_in_rig = Rotate(q_f, points_[i], want[3] ? &d_qf : nullptr) + t_f;
    const Eigen::Vector3d point_in_cam = Rotate(q_c, point_in_rig, want[1] ? &d_qc : nullptr) + t_c;
    LensStep step;
    if (!lens(intrinsics, point_in_cam, any, &step)) return false;
    ProjectionJacobian projection;
    ApplyPinholeStep(pinhole, step, any, &projection);
    residuals[2 * i] = projection.pixel.x() - pixels_[i].x();
    residuals[2 * i + 1] = projection.pixel.y() - pixels_[i].y();
    if (!any) continue;
    const auto rows = [&](int b) { return jacobians[b] + 2 * i * kBlockSizes[b]; };
    if (want[0]) {
      Eigen::Map<Eigen::Matrix<double, 2, 10, Eigen::RowMajor>>(rows(0)) = projection.d_intrinsics;
    }
    if (want[1]) {
      Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>>(rows(1)) = projection.d_point * d_qc;
    }
    if (want[2])
      Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>(rows(2)) = projection.d_point;
    if (want[3]) {
      Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>>(rows(3)) =
          projection.d_point * r_c * d_qf;
    }
    if (want[4]) {
      Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>(rows(4)) = projection.d_point * r_c;
    }
  }
  return true;
}

}  // namespace calibench
