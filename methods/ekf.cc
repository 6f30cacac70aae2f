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

#include <cmath>
#include <sstream>

#include "methods/ekf_model.h"
#include "methods/method.h"
#include "util/status.h"

namespace calibench {
namespace {

constexpr int kN = CameraEstimate::kCovarianceSize;  // 11.
using Jet = ceres::Jet<double, kN>;
using StateVector = Eigen::Matrix<double, kN, 1>;
using StateMatrix = Eigen::Matrix<double, kN, kN>;

// The pixel of `point_in_parent` for state x (T = double or Jet): methods/ekf_model.h's mount
// (x[5..7], x[8..10]) and intrinsics (x[0..4]).
template <typename T>
bool ProjectState(const T* x, const Eigen::Matrix3d& r_c_nominal, const CameraIntrinsics& lens,
                  const Eigen::Vector3d& point_in_parent, T* pixel) {
  T point_in_cam[3];
  MountPointInCam(x + 5, x + 8, r_c_nominal, point_in_parent, point_in_cam);
  return ProjectWithIntrinsics(x, lens, point_in_cam, pixel);
}

class EkfMethod final : public FilterMethod<EkfFilterOptions> {
 public:
  std::unique_ptr<Method> Clone() const override { return std::make_unique<EkfMethod>(*this); }

  MethodResult Run(const MethodInput& input, EstimateSink* sink) const override {
    const SummaryClock clock;
    MethodResult result;
    if (RefuseWideLens(input, "ekf", &result)) return result;
    const MethodResult& init = input.Window(0.0, start_.init_window_s).Prerequisite(start_.init);
    if (!init.IsUsable() || !init.estimate.has_camera) {
      return clock.Finish(&result, MethodStatus::kFailed,
                          "initialisation (" + start_.init + ") failed: " + init.message);
    }
    const CameraIntrinsics lens = init.estimate.intrinsics;  // Its distortion stays fixed.
    StateVector x, q;
    Eigen::Matrix3d r_c;
    StateMatrix p;
    Start(init.estimate, &x, &r_c, &p, &q);
    // The estimated parameters (phi without estimate_skew is not one).
    std::vector<int> free;
    for (int i = 0; i < kN; ++i) {
      if (i != 2 || filter_.estimate_skew) free.push_back(i);
    }
    const int m = static_cast<int>(free.size());
    const FrameSet& frames = input.Frames();
    double last_t = start_.init_window_s;
    int updates = 0, skipped = 0;
    for (size_t k = 0; k < frames.views.size(); ++k) {
      const double t = frames.times_s[k];
      if (t <= start_.init_window_s) continue;
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
                          "no frame after init_window_s = " + std::to_string(start_.init_window_s) +
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
    StateVector p0;
    filter_.Start(start, x, &p0, q);
    *r_c = start.parent_from_cam.rotation;
    *p = p0.array().square().matrix().asDiagonal();
  }

  // One frame's (iterated) measurement update over the `free` states (methods/ekf_model.h's
  // InformationUpdate): each iteration relinearises the view's projections at the current *x.
  // *posterior is P+. False when the information is not positive definite (a degenerate frame).
  bool Update(const View& view, const Eigen::Matrix3d& r_c, const CameraIntrinsics& lens,
              const std::vector<int>& free, const StateMatrix& p, StateVector* x,
              Eigen::MatrixXd* posterior) const {
    const int m = static_cast<int>(free.size());
    Eigen::VectorXd x_dynamic = *x;
    const bool ok = InformationUpdate(
        p, free, filter_.pixel_sigma_px, filter_.iterations,
        [&](const Eigen::VectorXd& at, const AddMeasurementRow& add) {
          Jet xj[kN];
          for (int i = 0; i < kN; ++i) xj[i] = Jet(at[i], i);
          Eigen::RowVectorXd h(m);
          for (size_t i = 0; i < view.points.size(); ++i) {
            Jet pixel[2];
            if (!ProjectState(xj, r_c, lens, view.points[i], pixel)) continue;
            for (int c = 0; c < 2; ++c) {
              for (int a = 0; a < m; ++a) h[a] = pixel[c].v[free[a]];
              add(h, view.pixels[i][c] - pixel[c].a);
            }
          }
        },
        &x_dynamic, posterior);
    *x = x_dynamic;
    return ok;
  }

  static CameraEstimate EstimateOf(const StateVector& x, const Eigen::Matrix3d& r_c,
                                   const CameraIntrinsics& lens, const StateMatrix& p) {
    return CameraEstimateOf(x, r_c, lens, p);
  }
};

}  // namespace

std::unique_ptr<Method> MakeEkfMethod() { return std::make_unique<EkfMethod>(); }

}  // namespace calibench
