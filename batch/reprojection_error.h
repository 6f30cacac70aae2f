// The reprojection residual of every Ceres-based estimator (after Ceres'
// examples/snavely_reprojection_error.h):
//
//     residual = Project(intrinsics, q * point_in_object + t) - pixel        [px]
//
// Parameter blocks:
//   0: intrinsics[10]  the lens family's raw order (camera/camera.h); radtan: fku, fkv, phi_rad,
//                      u0, v0, k1, k2, p1, p2, k3; equidistant: ..., k1, k2, k3, k4, unused;
//                      unified: ..., xi, k1, k2, p1, p2; eucm: ..., alpha, beta, 3 unused;
//                      double-sphere: ..., xi, alpha, 3 unused
//   1: rotation[4]     cam_from_object quaternion, Eigen order (x, y, z, w);
//                      EigenQuaternionManifold
//   2: translation[3]  cam_from_object translation
// A point outside the lens' valid region (behind the camera for radtan and equidistant) makes the
// evaluation fail (Ceres then shortens the step) instead of producing a silent zero.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "camera/camera.h"

namespace calibench {

// The Jet reference for every lens family.
struct ReprojectionError {
  ReprojectionError(const Eigen::Vector2d& measured_pixel, const Eigen::Vector3d& point,
                    LensFamily lens_family = LensFamily::kRadTan)
      : pixel(measured_pixel), point_in_object(point), family(lens_family) {}

  template <typename T>
  bool operator()(const T* intrinsics, const T* rotation, const T* translation, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> cam_from_object_q(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> cam_from_object_t(translation);
    const Eigen::Matrix<T, 3, 1> point_in_cam =
        cam_from_object_q * point_in_object.cast<T>() + cam_from_object_t;
    T projected[2];
    if (!ProjectLens(family, intrinsics, point_in_cam.data(), projected)) return false;
    residual[0] = projected[0] - T(pixel.x());
    residual[1] = projected[1] - T(pixel.y());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& pixel,
                                     const Eigen::Vector3d& point_in_object,
                                     LensFamily family = LensFamily::kRadTan) {
    return new ceres::AutoDiffCostFunction<ReprojectionError, 2, PinholeSkewCamera::kNumParams, 4,
                                           3>(
        new ReprojectionError(pixel, point_in_object, family));
  }

  Eigen::Vector2d pixel;
  Eigen::Vector3d point_in_object;
  LensFamily family;
};

// The same residual with hand-written Jacobians (batch/projection_jacobian.h, every lens family):
// the hot path of every batch calibration, 5-8x faster per solver iteration than the
// Jet<double, 17> reference (measured by bench/micro/calibrate_benchmark.cc). Same parameter
// blocks as ReprojectionError; its Jacobians are checked against ReprojectionError's ceres::Jet
// derivatives in tests/batch/refine_test.cc. Chain: pixel <- (xd, yd) <- X = q * point + t (the
// lens step of projection_jacobian.h), with
//   d(q * p)/dw = 2 (q_v x p),
//   d(q * p)/dq_v = -2 w [p]x - 2 [q_v x p]x - 2 [q_v]x [p]x     (Eigen's q * p formula, unit q).
class ReprojectionCostFunction final
    : public ceres::SizedCostFunction<2, PinholeSkewCamera::kNumParams, 4, 3> {
 public:
  ReprojectionCostFunction(const Eigen::Vector2d& measured_pixel, const Eigen::Vector3d& point,
                           LensFamily family = LensFamily::kRadTan)
      : pixel_(measured_pixel), point_in_object_(point), family_(family) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::Vector2d pixel_;
  Eigen::Vector3d point_in_object_;
  LensFamily family_;
};

// All points of one view in one residual block (2 n residuals, same blocks as above). With a
// plain least-squares loss the cost is identical to n ReprojectionCostFunction blocks, and Ceres'
// per-block overhead is paid once per view instead of once per point (3x faster on 150-point
// boards). A robust loss would act on the view's summed squares instead: use per-point blocks.
// The lens family is dispatched once per evaluation of the view, not per point.
class ViewReprojectionCostFunction final : public ceres::CostFunction {
 public:
  ViewReprojectionCostFunction(std::vector<Eigen::Vector3d> points,
                               std::vector<Eigen::Vector2d> pixels,
                               LensFamily family = LensFamily::kRadTan);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::vector<Eigen::Vector3d> points_;
  std::vector<Eigen::Vector2d> pixels_;
  LensFamily family_;
};

}  // namespace calibench
