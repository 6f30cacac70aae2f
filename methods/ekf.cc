// Method `ekf`: an (iterated) extended Kalman filter on the camera's parameters, as robotics
// practitioners run online calibration (OpenVINS, ROVIO; spec dynamic-calibration.md).
//
// State (11, the layout of camera/estimate.h's covariance):
//   x = [f*ku, f*kv, phi (rad), u0, v0, dtheta (3, rad), x_C (3, m)],
// the rotation as an error state about a nominal R_C: R_C = Exp(dtheta) R_C_nominal (parent
// frame), dtheta reset to 0 after every update (R_C_nominal <- Exp(dtheta) R_C_nominal).
// Process: a random walk per parameter group over the time dt between frames,
//   P <- P + dt diag(q_focal, q_focal, q_skew, q_center, q_center, q_rotation x3, q_position x3).
// Measurement: every corner of a frame through the projection model,
//   z_i = Project(A(x), R_C^T (x_bar_i - x_C)) + n,  n ~ N(0, pixel_sigma_px^2 I),
// its Jacobian H from ceres::Jet<double, 11>; the update in information form (R is diagonal):
//   P+ = (P^-1 + H^T H / sigma^2)^-1,   x_(k+1) = x- + P+ H^T (z - h(x_k) - H (x- - x_k)) /
//   sigma^2,
// `iterations` times (1: the EKF; more: the iterated EKF, Gauss-Newton on the MAP cost).
// Start: the estimate of `init` (an instance or type: dlt, zhang, ceres) on the first
// init_window_s seconds, with diagonal P0 (p0_*); the filter runs on the frames after it. A
// parameter not estimated (phi without estimate_skew) keeps zero variance. The distortion of the
// start is kept fixed. It reports its estimate and covariance after every frame.
#include <ceres/jet.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <sstream>

#include "methods/method.h"
#include "util/status.h"

namespace calibench {
namespace {

constexpr int kN = CameraEstimate::kCovarianceSize;  // 11.
using Jet = ceres::Jet<double, kN>;
using StateVector = Eigen::Matrix<double, kN, 1>;
using StateMatrix = Eigen::Matrix<double, kN, kN>;

// The pixel of `point_in_parent` for state x (T = double or Jet).
template <typename T>
bool ProjectState(const T* x, const Eigen::Matrix3d& r_c_nominal, const CameraIntrinsics& lens,
                  const Eigen::Vector3d& point_in_parent, T* pixel) {
  // point_in_cam = R_C^T (x_bar - x_C) = R_nominal^T Exp(-dtheta) (x_bar - x_C).
  const T v[3] = {T(point_in_parent.x()) - x[8], T(point_in_parent.y()) - x[9],
                  T(point_in_parent.z()) - x[10]};
  const T minus_dtheta[3] = {-x[5], -x[6], -x[7]};
  T w[3];
  ceres::AngleAxisRotatePoint(minus_dtheta, v, w);
  T point_in_cam[3];
  for (int r = 0; r < 3; ++r) {
    point_in_cam[r] =
        T(r_c_nominal(0, r)) * w[0] + T(r_c_nominal(1, r)) * w[1] + T(r_c_nominal(2, r)) * w[2];
  }
  const std::array<double, 10> lens_params = lens.Params();  // Distortion slots 5..9.
  T params[PinholeSkewCamera::kNumParams];
  for (int i = 0; i < PinholeSkewCamera::kNumParams; ++i) {
    params[i] = i < 5 ? x[i] : T(lens_params[i]);
  }
  return ProjectLens(lens.family, params, point_in_cam, pixel);
}

class EkfMethod final : public Method {
 public:
  std::unique_ptr<Method> Clone() const override { return std::make_unique<EkfMethod>(*this); }

  void VisitOptions(OptionVisitor* v) override {
    v->Field({"init", "",
              "The method it starts from, solved on the first init_window_s: an instance of the "
              "scenario, or a type's default (dlt, zhang, ceres)."},
             &init_, {});
    v->Field({"init_window_s", "s",
              "The start's data: the first seconds of the trial; the filter runs on the frames "
              "after it."},
             &init_window_s_);
    v->Field({"estimate_skew", "",
              "Estimate the skew angle φ; false keeps the start's φ, with zero variance."},
             &estimate_skew_);
    v->Field({"pixel_sigma_px", "px", "Measurement noise std per pixel coordinate."},
             &pixel_sigma_px_);
    v->Field({"iterations", "", "Updates per frame: 1, the EKF; more, the iterated EKF (≤ 20)."},
             &iterations_);
    v->Field({"q_focal_px2_s", "px²/s", "Random-walk variance per second of f·ku and f·kv."},
             &q_focal_);
    v->Field({"q_center_px2_s", "px²/s", "Random-walk variance per second of u0 and v0."},
             &q_center_);
    v->Field({"q_skew_rad2_s", "rad²/s", "Random-walk variance per second of φ."}, &q_skew_);
    v->Field({"q_rotation_rad2_s", "rad²/s",
              "Random-walk variance per second of each axis of the extrinsic rotation (ROVIO: "
              "1e-8)."},
             &q_rotation_);
    v->Field({"q_position_m2_s", "m²/s", "Random-walk variance per second of each axis of x_C."},
             &q_position_);
    v->Field({"p0_focal_px", "px", "Initial std of f·ku and f·kv about the start."}, &p0_focal_);
    v->Field({"p0_center_px", "px", "Initial std of u0 and v0 about the start."}, &p0_center_);
    v->Field({"p0_skew_deg", "deg", "Initial std of φ about the start."}, &p0_skew_deg_);
    v->Field({"p0_rotation_deg", "deg",
              "Initial std of each axis of the extrinsic rotation about the start."},
             &p0_rotation_deg_);
    v->Field({"p0_position_m", "m", "Initial std of each axis of x_C about the start."},
             &p0_position_);
  }

  bool Check(std::string* why) const override {
    std::ostringstream msg;
    const double q[5] = {q_focal_, q_center_, q_skew_, q_rotation_, q_position_};
    const double p0[5] = {p0_focal_, p0_center_, p0_skew_deg_, p0_rotation_deg_, p0_position_};
    if (init_.empty()) {
      msg << "init must name the method it starts from (dlt, zhang, ceres or an instance)";
    } else if (!(init_window_s_ > 0 && std::isfinite(init_window_s_))) {
      msg << "init_window_s must be > 0, got " << init_window_s_;
    } else if (!(pixel_sigma_px_ > 0 && std::isfinite(pixel_sigma_px_))) {
      msg << "pixel_sigma_px must be > 0, got " << pixel_sigma_px_;
    } else if (iterations_ < 1 || iterations_ > 20) {
      msg << "iterations must lie in [1, 20], got " << iterations_;
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

  std::vector<std::string> Prerequisites() const override { return {init_}; }

  MethodResult Run(const MethodInput& input, EstimateSink* sink) const override {
    const SummaryClock clock;
    MethodResult result;
    if (RefuseWideLens(input, "ekf", &result)) return result;
    const MethodResult& init = input.Window(0.0, init_window_s_).Prerequisite(init_);
    if (!init.IsUsable() || !init.estimate.has_camera) {
      return clock.Finish(&result, MethodStatus::kFailed,
                          "initialisation (" + init_ + ") failed: " + init.message);
    }
    const CameraIntrinsics lens = init.estimate.intrinsics;  // Its distortion stays fixed.
    StateVector x, q;
    Eigen::Matrix3d r_c;
    StateMatrix p;
    Start(init.estimate, &x, &r_c, &p, &q);
    // The estimated parameters (phi without estimate_skew is not one).
    std::vector<int> free;
    for (int i = 0; i < kN; ++i) {
      if (i != 2 || estimate_skew_) free.push_back(i);
    }
    const int m = static_cast<int>(free.size());
    const FrameSet& frames = input.Frames();
    double last_t = init_window_s_;
    int updates = 0, skipped = 0;
    for (size_t k = 0; k < frames.views.size(); ++k) {
      const double t = frames.times_s[k];
      if (t <= init_window_s_) continue;
      const View& view = frames.views[k];
      p += (t - last_t) * StateMatrix(q.asDiagonal());  // Random walk since the last frame.
      last_t = t;
      if (view.points.empty()) {
        ++skipped;
        continue;
      }
      const StateVector x_prior = x;
      Eigen::MatrixXd posterior;
      if (!Update(view, r_c, lens, free, p, &x, &posterior) || !x.allFinite()) {
        x = x_prior;  // A degenerate frame: keep the prediction.
        ++skipped;
        continue;
      }
      p.setZero();
      for (int a = 0; a < m; ++a) {
        for (int b = 0; b < m; ++b) p(free[a], free[b]) = posterior(a, b);
      }
      // Reset the error state into the nominal rotation.
      r_c = ExpSO3(x.segment<3>(5)) * r_c;
      x.segment<3>(5).setZero();
      ++updates;
      if (sink != nullptr) sink->OnEstimate(t, EstimateOf(x, r_c, lens, p));
    }
    result.iterations = updates;
    if (updates == 0) {
      return clock.Finish(&result, MethodStatus::kFailed,
                          "no frame after init_window_s = " + std::to_string(init_window_s_) +
                              " s updated the filter");
    }
    result.estimate = EstimateOf(x, r_c, lens, p);
    std::ostringstream note;
    note << updates << " updates";
    if (skipped > 0) note << ", " << skipped << " frames skipped (no points or degenerate)";
    return clock.Finish(&result, MethodStatus::kOk, note.str());
  }

 private:
  // The filter's start from the initialisation's estimate: the state (intrinsics, a zero rotation
  // error, x_C), the nominal rotation R_C, the initial covariance and the process noise per second.
  void Start(const CameraEstimate& start, StateVector* x, Eigen::Matrix3d* r_c, StateMatrix* p,
             StateVector* q) const {
    *x << start.intrinsics.fku_px, start.intrinsics.fkv_px, start.intrinsics.phi_deg * M_PI / 180,
        start.intrinsics.u0_px, start.intrinsics.v0_px, 0, 0, 0, start.parent_from_cam.translation;
    *r_c = start.parent_from_cam.rotation;
    const double deg = M_PI / 180;
    StateVector p0;
    p0 << p0_focal_, p0_focal_, p0_skew_deg_ * deg, p0_center_, p0_center_,
        Eigen::Vector3d::Constant(p0_rotation_deg_ * deg), Eigen::Vector3d::Constant(p0_position_);
    *q << q_focal_, q_focal_, q_skew_, q_center_, q_center_, Eigen::Vector3d::Constant(q_rotation_),
        Eigen::Vector3d::Constant(q_position_);
    if (!estimate_skew_) p0[2] = (*q)[2] = 0;
    *p = p0.array().square().matrix().asDiagonal();
  }

  // One frame's (iterated) measurement update in information form over the `free` states: prior
  // *x with covariance p; each iteration relinearises the view's projections at the current *x,
  // x_(k+1) = x- + P+ g with g = H^T (r - H (x- - x_k)) / s^2. *posterior is P+. False when the
  // information is not positive definite (a degenerate frame).
  bool Update(const View& view, const Eigen::Matrix3d& r_c, const CameraIntrinsics& lens,
              const std::vector<int>& free, const StateMatrix& p, StateVector* x,
              Eigen::MatrixXd* posterior) const {
    const int m = static_cast<int>(free.size());
    const double inv_var = 1.0 / (pixel_sigma_px_ * pixel_sigma_px_);
    const StateVector x_prior = *x;
    Eigen::MatrixXd p_prior(m, m);
    for (int a = 0; a < m; ++a) {
      for (int b = 0; b < m; ++b) p_prior(a, b) = p(free[a], free[b]);
    }
    const Eigen::LDLT<Eigen::MatrixXd> prior(p_prior);
    const Eigen::MatrixXd prior_information = prior.solve(Eigen::MatrixXd::Identity(m, m));
    posterior->resize(m, m);
    for (int it = 0; it < iterations_; ++it) {
      Eigen::MatrixXd information = prior_information;
      Eigen::VectorXd gradient = Eigen::VectorXd::Zero(m);  // H^T (r - H (x- - x_k)) / s^2.
      Jet xj[kN];
      for (int i = 0; i < kN; ++i) xj[i] = Jet((*x)[i], i);
      Eigen::VectorXd delta_prior(m);
      for (int a = 0; a < m; ++a) delta_prior[a] = x_prior[free[a]] - (*x)[free[a]];
      for (size_t i = 0; i < view.points.size(); ++i) {
        Jet pixel[2];
        if (!ProjectState(xj, r_c, lens, view.points[i], pixel)) continue;
        for (int c = 0; c < 2; ++c) {
          Eigen::RowVectorXd h(m);
          for (int a = 0; a < m; ++a) h[a] = pixel[c].v[free[a]];
          const double r = view.pixels[i][c] - pixel[c].a;
          information.noalias() += inv_var * h.transpose() * h;
          gradient.noalias() += inv_var * h.transpose() * (r - h.dot(delta_prior));
        }
      }
      const Eigen::LLT<Eigen::MatrixXd> llt(information);
      if (llt.info() != Eigen::Success) return false;
      *posterior = llt.solve(Eigen::MatrixXd::Identity(m, m));
      // x_(k+1) = x- + P+ g, g = H^T (r - H (x- - x_k)) / s^2.
      const Eigen::VectorXd step = *posterior * gradient;
      for (int a = 0; a < m; ++a) (*x)[free[a]] = x_prior[free[a]] + step[a];
    }
    return true;
  }

  static CameraEstimate EstimateOf(const StateVector& x, const Eigen::Matrix3d& r_c,
                                   const CameraIntrinsics& lens, const StateMatrix& p) {
    CameraEstimate e;
    e.has_camera = true;
    e.intrinsics = lens;
    e.intrinsics.fku_px = x[0];
    e.intrinsics.fkv_px = x[1];
    e.intrinsics.phi_deg = x[2] * 180 / M_PI;
    e.intrinsics.u0_px = x[3];
    e.intrinsics.v0_px = x[4];
    e.parent_from_cam = {ProjectToSO3(r_c), x.segment<3>(8)};
    e.cam_from_parent = e.parent_from_cam.Inverse();
    e.covariance = p;
    for (int i = 0; i < 5; ++i) {
      if (p(i, i) > 0) e.intrinsics_std[i] = std::sqrt(p(i, i));
    }
    return e;
  }

  std::string init_ = "dlt";
  double init_window_s_ = 2.0;  // The start's data (s).
  bool estimate_skew_ = true;
  double pixel_sigma_px_ = 0.3;  // Measurement noise per pixel coordinate.
  int iterations_ = 1;           // 1: EKF; > 1: iterated EKF.
  // Random walks (variance per second): ROVIO's 1e-8 rad^2/s on the extrinsic rotation.
  double q_focal_ = 1e-4, q_center_ = 1e-4, q_skew_ = 1e-10, q_rotation_ = 1e-8, q_position_ = 1e-8;
  // Initial standard deviations about the start.
  double p0_focal_ = 10.0, p0_center_ = 10.0, p0_skew_deg_ = 0.5, p0_rotation_deg_ = 1.0,
         p0_position_ = 0.05;
};

}  // namespace

std::unique_ptr<Method> MakeEkfMethod() { return std::make_unique<EkfMethod>(); }

}  // namespace calibench
