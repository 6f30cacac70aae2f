#include "methods/ekf_model.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <sstream>

#include "camera/pose.h"

namespace calibench {

bool InformationUpdate(const Eigen::MatrixXd& p, const std::vector<int>& free,
                       double pixel_sigma_px, int iterations,
                       const LineariseMeasurements& linearise, Eigen::VectorXd* x,
                       Eigen::MatrixXd* posterior) {
  const int m = static_cast<int>(free.size());
  const double inv_var = 1.0 / (pixel_sigma_px * pixel_sigma_px);
  const Eigen::VectorXd x_prior = *x;
  Eigen::MatrixXd p_prior(m, m);
  for (int a = 0; a < m; ++a) {
    for (int b = 0; b < m; ++b) p_prior(a, b) = p(free[a], free[b]);
  }
  const Eigen::LDLT<Eigen::MatrixXd> prior(p_prior);
  const Eigen::MatrixXd prior_information = prior.solve(Eigen::MatrixXd::Identity(m, m));
  posterior->resize(m, m);
  for (int it = 0; it < iterations; ++it) {
    Eigen::MatrixXd information = prior_information;
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(m);  // H^T (r - H (x- - x_k)) / s^2.
    Eigen::VectorXd delta_prior(m);
    for (int a = 0; a < m; ++a) delta_prior[a] = x_prior[free[a]] - (*x)[free[a]];
    linearise(*x, [&](const Eigen::RowVectorXd& h, double r) {
      information.noalias() += inv_var * h.transpose() * h;
      gradient.noalias() += inv_var * h.transpose() * (r - h.dot(delta_prior));
    });
    const Eigen::LLT<Eigen::MatrixXd> llt(information);
    if (llt.info() != Eigen::Success) return false;
    *posterior = llt.solve(Eigen::MatrixXd::Identity(m, m));
    // x_(k+1) = x- + P+ g, g = H^T (r - H (x- - x_k)) / s^2.
    const Eigen::VectorXd step = *posterior * gradient;
    for (int a = 0; a < m; ++a) (*x)[free[a]] = x_prior[free[a]] + step[a];
  }
  return true;
}

void EkfStartOptions::Visit(OptionVisitor* v) {
  v->Field({"init", "",
            "The method it starts from, solved on the first init_window_s: an instance of the "
            "scenario, or a type's default (dlt, zhang, ceres)."},
           &init, {});
  v->Field({"init_window_s", "s",
            "The start's data: the first seconds of the trial; the filter runs on the frames "
            "after it."},
           &init_window_s);
}

bool EkfStartOptions::Check(std::string* why) const {
  std::ostringstream msg;
  if (init.empty()) {
    msg << "init must name the method it starts from (dlt, zhang, ceres or an instance)";
  } else if (!(init_window_s > 0 && std::isfinite(init_window_s))) {
    msg << "init_window_s must be > 0, got " << init_window_s;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

void EkfFilterOptions::Visit(OptionVisitor* v) {
  v->Field({"estimate_skew", "",
            "Estimate the skew angle φ; false keeps the start's φ, with zero variance."},
           &estimate_skew);
  v->Field({"pixel_sigma_px", "px", "Measurement noise std per pixel coordinate."},
           &pixel_sigma_px);
  v->Field({"iterations", "", "Updates per frame: 1, the EKF; more, the iterated EKF (≤ 20)."},
           &iterations);
  v->Field({"q_focal_px2_s", "px²/s", "Random-walk variance per second of f·ku and f·kv."},
           &q_focal_px2_s);
  v->Field({"q_center_px2_s", "px²/s", "Random-walk variance per second of u0 and v0."},
           &q_center_px2_s);
  v->Field({"q_skew_rad2_s", "rad²/s", "Random-walk variance per second of φ."}, &q_skew_rad2_s);
  v->Field({"q_rotation_rad2_s", "rad²/s",
            "Random-walk variance per second of each axis of the extrinsic rotation (ROVIO: "
            "1e-8)."},
           &q_rotation_rad2_s);
  v->Field({"q_position_m2_s", "m²/s", "Random-walk variance per second of each axis of x_C."},
           &q_position_m2_s);
  v->Field({"p0_focal_px", "px", "Initial std of f·ku and f·kv about the start."}, &p0_focal_px);
  v->Field({"p0_center_px", "px", "Initial std of u0 and v0 about the start."}, &p0_center_px);
  v->Field({"p0_skew_deg", "deg", "Initial std of φ about the start."}, &p0_skew_deg);
  v->Field({"p0_rotation_deg", "deg",
            "Initial std of each axis of the extrinsic rotation about the start."},
           &p0_rotation_deg);
  v->Field({"p0_position_m", "m", "Initial std of each axis of x_C about the start."},
           &p0_position_m);
}

bool EkfFilterOptions::Check(std::string* why) const {
  std::ostringstream msg;
  const double q[5] = {q_focal_px2_s, q_center_px2_s, q_skew_rad2_s, q_rotation_rad2_s,
                       q_position_m2_s};
  const double p0[5] = {p0_focal_px, p0_center_px, p0_skew_deg, p0_rotation_deg, p0_position_m};
  if (!(pixel_sigma_px > 0 && std::isfinite(pixel_sigma_px))) {
    msg << "pixel_sigma_px must be > 0, got " << pixel_sigma_px;
  } else if (iterations < 1 || iterations > 20) {
    msg << "iterations must lie in [1, 20], got " << iterations;
  }
  for (double x : q) {
    if (msg.str().empty() && !(x >= 0 && std::isfinite(x))) {
      msg << "process noise q_* must be >= 0 and finite, got " << x;
    }
  }
  for (double x : p0) {
    if (msg.str().empty() && !(x > 0 && std::isfinite(x))) {
      msg << "initial std p0_* must be > 0 and finite, got " << x;
    }
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

void EkfFilterOptions::Start(const CameraEstimate& start, CameraStates* x, CameraStates* p0_std,
                             CameraStates* q) const {
  *x << start.intrinsics.fku_px, start.intrinsics.fkv_px, start.intrinsics.phi_deg * M_PI / 180,
      start.intrinsics.u0_px, start.intrinsics.v0_px, 0, 0, 0, start.parent_from_cam.translation;
  const double deg = M_PI / 180;
  *p0_std << p0_focal_px, p0_focal_px, p0_skew_deg * deg, p0_center_px, p0_center_px,
      Eigen::Vector3d::Constant(p0_rotation_deg * deg), Eigen::Vector3d::Constant(p0_position_m);
  *q << q_focal_px2_s, q_focal_px2_s, q_skew_rad2_s, q_center_px2_s, q_center_px2_s,
      Eigen::Vector3d::Constant(q_rotation_rad2_s), Eigen::Vector3d::Constant(q_position_m2_s);
  if (!estimate_skew) (*p0_std)[2] = (*q)[2] = 0;
}

CameraEstimate CameraEstimateOf(const CameraStates& x, const Eigen::Matrix3d& r_c_nominal,
                                const CameraIntrinsics& lens, const Eigen::MatrixXd& p) {
  CameraEstimate e;
  e.has_camera = true;
  e.intrinsics = lens;
  e.intrinsics.fku_px = x[0];
  e.intrinsics.fkv_px = x[1];
  e.intrinsics.phi_deg = x[2] * 180 / M_PI;
  e.intrinsics.u0_px = x[3];
  e.intrinsics.v0_px = x[4];
  e.parent_from_cam = {ProjectToSO3(r_c_nominal), x.segment<3>(8)};
  e.cam_from_parent = e.parent_from_cam.Inverse();
  e.covariance = p;
  for (int i = 0; i < 5; ++i) {
    if (p(i, i) > 0) e.intrinsics_std[i] = std::sqrt(p(i, i));
  }
  return e;
}

}  // namespace calibench
