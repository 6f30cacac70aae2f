// The pieces the Kalman filters on camera parameters share (methods/ekf.cc, one camera;
// methods/ekf_rig.h, a rig): the projection of a point of the parent frame through a mount and
// intrinsics held as filter states (double or ceres::Jet, for the Jacobian), and the (iterated)
// measurement update in information form, and the options, start and estimate of one camera's
// 11 states (camera/estimate.h's covariance layout).
//
// Mount: the camera's rotation as an error state about a nominal, R_C = Exp(dtheta) R_nominal
// (parent frame), and its centre x_C in the parent frame:
//   point_in_cam = R_C^T (x_bar - x_C) = R_nominal^T Exp(-dtheta) (x_bar - x_C).
// Intrinsics: [f*ku, f*kv, phi (rad), u0, v0] (the first five of camera/estimate.h's layout); the
// lens's distortion coefficients are constants (the filters keep the start's).
//
// Update (R = sigma^2 I): with the prior x- (covariance P- over the `free` states) and a
// linearisation at x_k giving rows h (d pixel / d free states) and residuals r = z - h(x_k),
//   P+ = (P-^-1 + sum h^T h / sigma^2)^-1,
//   x_(k+1) = x- + P+ sum h^T (r - h (x- - x_k)) / sigma^2,
// `iterations` times from x_0 = x- (1: the EKF; more: the iterated EKF, Gauss-Newton on the MAP
// cost). States not in `free` are untouched and are not part of P+.
#pragma once

#include <ceres/rotation.h>

#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/estimate.h"
#include "methods/method.h"

namespace calibench {

// point_in_cam of `point_in_parent` for the mount (dtheta[3], x_c[3]) about `r_nominal`.
template <typename T>
void MountPointInCam(const T* dtheta, const T* x_c, const Eigen::Matrix3d& r_nominal,
                     const Eigen::Vector3d& point_in_parent, T* point_in_cam) {
  const T v[3] = {T(point_in_parent.x()) - x_c[0], T(point_in_parent.y()) - x_c[1],
                  T(point_in_parent.z()) - x_c[2]};
  const T minus_dtheta[3] = {-dtheta[0], -dtheta[1], -dtheta[2]};
  T w[3];
  ceres::AngleAxisRotatePoint(minus_dtheta, v, w);
  for (int r = 0; r < 3; ++r) {
    point_in_cam[r] =
        T(r_nominal(0, r)) * w[0] + T(r_nominal(1, r)) * w[1] + T(r_nominal(2, r)) * w[2];
  }
}

// The pixel of `point_in_cam` through the intrinsics k[5] (f*ku, f*kv, phi rad, u0, v0) and the
// constant distortion of `lens`. False where the lens does not image the point.
template <typename T>
bool ProjectWithIntrinsics(const T* k, const CameraIntrinsics& lens, const T* point_in_cam,
                           T* pixel) {
  const std::array<double, 10> lens_params = lens.Params();  // Distortion slots 5..9.
  T params[PinholeSkewCamera::kNumParams];
  for (int i = 0; i < PinholeSkewCamera::kNumParams; ++i) {
    params[i] = i < 5 ? k[i] : T(lens_params[i]);
  }
  return ProjectLens(lens.family, params, point_in_cam, pixel);
}

// Hands one measurement row to the update: h over the free states, r = z - h(x_k).
using AddMeasurementRow = std::function<void(const Eigen::RowVectorXd& h, double r)>;
// Linearises every measurement at the state x (full size), calling `add` once per row.
using LineariseMeasurements =
    std::function<void(const Eigen::VectorXd& x, const AddMeasurementRow& add)>;

// The update of the header comment on *x (full state; only the free entries change), prior
// covariance `p` (full size; its free rows and columns are used). *posterior is P+ over `free`,
// in their order. False (and *x unspecified) when the information is not positive definite (a
// degenerate frame).
bool InformationUpdate(const Eigen::MatrixXd& p, const std::vector<int>& free,
                       double pixel_sigma_px, int iterations,
                       const LineariseMeasurements& linearise, Eigen::VectorXd* x,
                       Eigen::MatrixXd* posterior);

// One camera's 11 states [f*ku, f*kv, phi (rad), u0, v0, dtheta (3, rad), x_C (3, m)].
using CameraStates = Eigen::Matrix<double, CameraEstimate::kCovarianceSize, 1>;

// Where a filter starts: the estimate of the method `init` (an instance of the scenario or a
// type's default: dlt, zhang, ceres) on the first init_window_s seconds; the filter runs on the
// frames after it.
struct EkfStartOptions {
  std::string init = "dlt";
  double init_window_s = 2.0;  // The start's data (s).

  void Visit(OptionVisitor* v);
  bool Check(std::string* why) const;
};

// The filter options every camera's states share (method `ekf`'s and `ekf-rig`'s keys).
struct EkfFilterOptions {
  bool estimate_skew = true;    // false: phi stays the start's, with zero variance.
  double pixel_sigma_px = 0.3;  // Measurement noise per pixel coordinate.
  int iterations = 1;           // 1: EKF; > 1: iterated EKF (<= 20).
  // Random walks (variance per second): ROVIO's 1e-8 rad^2/s on the extrinsic rotation.
  double q_focal_px2_s = 1e-4, q_center_px2_s = 1e-4, q_skew_rad2_s = 1e-10,
         q_rotation_rad2_s = 1e-8, q_position_m2_s = 1e-8;
  // Initial standard deviations about the start.
  double p0_focal_px = 10.0, p0_center_px = 10.0, p0_skew_deg = 0.5, p0_rotation_deg = 1.0,
         p0_position_m = 0.05;

  void Visit(OptionVisitor* v);
  bool Check(std::string* why) const;
  // The states of a camera's start (a zero rotation error; R_C is the nominal), and the diagonals
  // of its initial standard deviations and of its process noise per second (phi's 0 without
  // estimate_skew).
  void Start(const CameraEstimate& start, CameraStates* x, CameraStates* p0_std,
             CameraStates* q) const;
};

// The options of a filter method (ekf, ekf_rig): where it starts, then its filter's options (a type
// with Visit and Check).
template <typename FilterOptions>
class FilterMethod : public Method {
 public:
  void VisitOptions(OptionVisitor* v) override {
    start_.Visit(v);
    filter_.Visit(v);
  }
  bool Check(std::string* why) const override { return start_.Check(why) && filter_.Check(why); }
  std::vector<std::string> Prerequisites() const override { return {start_.init}; }

 protected:
  EkfStartOptions start_;
  FilterOptions filter_;
};

// The estimate of a camera with states x about the nominal rotation r_c_nominal, the lens's
// distortion, and covariance p (11 x 11, camera/estimate.h's layout).
CameraEstimate CameraEstimateOf(const CameraStates& x, const Eigen::Matrix3d& r_c_nominal,
                                const CameraIntrinsics& lens, const Eigen::MatrixXd& p);

}  // namespace calibench
