// The reprojection residual of the rig refinement (batch/rig_refine.h): a board point X of frame f
// seen by camera c,
//
//     residual = Project(intrinsics_c, cam_from_rig_c * rig_from_board_f * X) - pixel      [px]
//
// Parameter blocks (both cost functions):
//   0: intrinsics[10]     camera c's, the lens family's raw order (batch/reprojection_error.h)
//   1: cam_rotation[4]    cam_from_rig_c quaternion, Eigen order (x, y, z, w); constant for c = 0
//   2: cam_translation[3] cam_from_rig_c translation (camera 0's centre seen from camera c)
//   3: board_rotation[4]  rig_from_board_f quaternion (x, y, z, w)
//   4: board_translation[3]
// Quaternion blocks carry Ceres' EigenQuaternionManifold. A point outside the lens' valid region
// makes the evaluation fail (Ceres shortens the step), as the single-camera residual.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "camera/camera.h"

namespace calibench {

// The ceres::Jet reference, one point.
struct RigReprojectionError {
  RigReprojectionError(const Eigen::Vector2d& measured_pixel, const Eigen::Vector3d& point,
                       LensFamily lens_family)
      : pixel(measured_pixel), point_in_board(point), family(lens_family) {}

  template <typename T>
  bool operator()(const T* intrinsics, const T* cam_rotation, const T* cam_translation,
                  const T* board_rotation, const T* board_translation, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> cam_from_rig_q(cam_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> cam_from_rig_t(cam_translation);
    const Eigen::Map<const Eigen::Quaternion<T>> rig_from_board_q(board_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> rig_from_board_t(board_translation);
    const Eigen::Matrix<T, 3, 1> point_in_rig =
        rig_from_board_q * point_in_board.cast<T>() + rig_from_board_t;
    const Eigen::Matrix<T, 3, 1> point_in_cam = cam_from_rig_q * point_in_rig + cam_from_rig_t;
    T projected[2];
    if (!ProjectLens(family, intrinsics, point_in_cam.data(), projected)) return false;
    residual[0] = projected[0] - T(pixel.x());
    residual[1] = projected[1] - T(pixel.y());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& pixel,
                                     const Eigen::Vector3d& point_in_board, LensFamily family) {
    return new ceres::AutoDiffCostFunction<RigReprojectionError, 2, PinholeSkewCamera::kNumParams,
                                           4, 3, 4, 3>(
        new RigReprojectionError(pixel, point_in_board, family));
  }

  Eigen::Vector2d pixel;
  Eigen::Vector3d point_in_board;
  LensFamily family;
};

// The same residual for every point of one view (camera c in frame f: 2 n residuals) with the
// hand-written Jacobians of batch/projection_jacobian.h, the hot path of RefineRig (checked against
// RigReprojectionError's ceres::Jet derivatives in tests/batch/rig_refine_test.cc). Chain, with
// Y = q_f * X + t_f and P = q_c * Y + t_c:
//   dP/dt_c = I,  dP/dq_c = dRot(q_c, Y),  dP/dt_f = R_c,  dP/dq_f = R_c dRot(q_f, X),
// where dRot(q, p) = d(q * p)/d(x, y, z, w) for a unit q (batch/reprojection_error.h).
// One point per view (a robust loss acts on each point) is a view of one point.
class RigViewCostFunction final : public ceres::CostFunction {
 public:
  RigViewCostFunction(std::vector<Eigen::Vector3d> points_in_board,
                      std::vector<Eigen::Vector2d> pixels, LensFamily family);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::vector<Eigen::Vector3d> points_;
  std::vector<Eigen::Vector2d> pixels_;
  LensFamily family_;
};

}  // namespace calibench
