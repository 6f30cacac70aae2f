#include "batch/reprojection_error.h"

#include "batch/projection_jacobian.h"
#include "camera/pose.h"

namespace calibench {
namespace {

// What every point of one evaluation shares: the parameter blocks, the pinhole step's constants
// and the family's lens step (chosen once).
struct EvaluationContext {
  EvaluationContext(double const* const* blocks, LensFamily family)
      : parameters(blocks), pinhole(blocks[0]), lens(LensStepOf(family)) {}
  double const* const* parameters;
  PinholeStep pinhole;
  LensStepFunction lens;
};

// The residual of one point and (where a pointer is non-null) its 2 x block-size row-major
// Jacobians.
bool EvaluatePoint(const EvaluationContext& c, const Eigen::Vector3d& p,
                   const Eigen::Vector2d& pixel, double* residuals, double* const* jacobians) {
  const double* q = c.parameters[1];  // x, y, z, w
  const double* t = c.parameters[2];
  const Eigen::Vector3d q_v(q[0], q[1], q[2]);
  const double w = q[3];
  // Eigen's unit-quaternion rotation: v + 2w (q_v x v) + 2 q_v x (q_v x v).
  const Eigen::Vector3d qxp = q_v.cross(p);
  const Eigen::Vector3d point_in_cam =
      p + 2.0 * w * qxp + 2.0 * q_v.cross(qxp) + Eigen::Vector3d(t[0], t[1], t[2]);
  const bool any = jacobians != nullptr &&
                   (jacobians[0] != nullptr || jacobians[1] != nullptr || jacobians[2] != nullptr);
  LensStep step;
  if (!c.lens(c.parameters[0], point_in_cam, any, &step)) return false;
  ProjectionJacobian projection;
  ApplyPinholeStep(c.pinhole, step, any, &projection);
  residuals[0] = projection.pixel.x() - pixel.x();
  residuals[1] = projection.pixel.y() - pixel.y();
  if (!any) return true;
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 10, Eigen::RowMajor>> j_intrinsics(jacobians[0]);
    j_intrinsics = projection.d_intrinsics;
  }
  if (jacobians[2] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> j_translation(jacobians[2]);
    j_translation = projection.d_point;
  }
  if (jacobians[1] != nullptr) {
    Eigen::Matrix<double, 3, 4> dx_dq;
    dx_dq.leftCols<3>() = -2.0 * w * Hat(p) - 2.0 * Hat(qxp) - 2.0 * Hat(q_v) * Hat(p);
    dx_dq.col(3) = 2.0 * qxp;
    Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>> j_rotation(jacobians[1]);
    j_rotation = projection.d_point * dx_dq;
  }
  return true;
}

}  // namespace

bool ReprojectionCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  return EvaluatePoint(EvaluationContext(parameters, family_), point_in_object_, pixel_, residuals,
                       jacobians);
}

ViewReprojectionCostFunction::ViewReprojectionCostFunction(std::vector<Eigen::Vector3d> points,
                                                           std::vector<Eigen::Vector2d> pixels,
                                                           LensFamily family)
    : points_(std::move(points)), pixels_(std::move(pixels)), family_(family) {
  set_num_residuals(2 * static_cast<int>(points_.size()));
  *mutable_parameter_block_sizes() = {PinholeSkewCamera::kNumParams, 4, 3};
}

bool ViewReprojectionCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  constexpr int kSizes[3] = {PinholeSkewCamera::kNumParams, 4, 3};
  const EvaluationContext context(parameters, family_);
  double* point_jacobians[3] = {nullptr, nullptr, nullptr};
  for (size_t i = 0; i < points_.size(); ++i) {
    if (jacobians != nullptr) {
      for (int b = 0; b < 3; ++b) {
        point_jacobians[b] = jacobians[b] ? jacobians[b] + 2 * i * kSizes[b] : nullptr;
      }
    }
    if (!EvaluatePoint(context, points_[i], pixels_[i], residuals + 2 * i,
                       jacobians ? point_jacobians : nullptr)) {
      return false;
    }
  }
  return true;
}

}  // namespace calibench
