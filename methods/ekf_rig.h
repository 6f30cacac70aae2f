// A joint extended Kalman filter on a camera rig (camera/rig.h: the rig frame is camera 0's) that
// carries the rig's relative poses in its state, beside each camera's intrinsics and camera 0's
// mount: the rig counterpart of method `ekf` (methods/ekf.cc), whose camera-0 states and update
// it shares (methods/ekf_model.h). Method `ekf-rig` runs it on a rig scenario's synchronised
// cameras.
//
// State, for N >= 2 cameras (11 N entries, per camera c a block of 11 at 11 c):
//   camera 0:  [f*ku, f*kv, phi (rad), u0, v0, dtheta_0 (3, rad), x_C (3, m)]   (method ekf's)
//   camera c:  [f*ku, f*kv, phi (rad), u0, v0, dtheta_c (3, rad), t_c (3, m)]
// with the rotations as error states about nominals, reset into them after every update:
//   R_C   = Exp(dtheta_0) R_C_nominal      camera 0's mount in the parent frame,
//   R_c0  = Exp(dtheta_c) R_c0_nominal     cam_c_from_cam_0's rotation (dtheta_c in camera c),
//   t_c   = cam_c_from_cam_0's translation (camera 0's centre seen from camera c, metres).
// Measurement: every corner of every camera at one synchronised instant, x_bar in the parent frame,
//   p_0 = R_C^T (x_bar - x_C),   p_c = R_c0 p_0 + t_c,
//   z = Project(A_c, lens_c, p_c) + n,   n ~ N(0, pixel_sigma_px^2 I),
// its Jacobian from ceres::Jet over the (at most 17) states a corner of camera c depends on
// (camera c's intrinsics, camera 0's mount, camera c's relative pose); the (iterated) update in
// information form over all states at once (ekf_model.h's InformationUpdate).
// Process: a random walk per group over the time dt between instants,
//   P <- P + dt diag(q): camera c's intrinsics q_focal, q_skew, q_center (EkfFilterOptions),
//   camera 0's mount q_rotation, q_position, each relative rotation q_rel_rotation and
//   translation q_rel_translation (RigEkfOptions).
// Start: every camera's own estimate (parent_from_cam_c and intrinsics, e.g. method ekf's `init`
// run per camera); cam_c_from_cam_0 = cam_c_from_parent * parent_from_cam_0; diagonal P0 (the
// p0_* options). Each camera's lens distortion stays its start's. A state not estimated (phi
// without estimate_skew) keeps zero variance.
// Reported: cam_c_from_cam_0 with the 6 x 6 covariance of [dtheta_c, t_c] (R_c0_true =
// Exp(dtheta_c) R_c0_hat), and each camera's estimate in camera/estimate.h's form, camera c's
// parent_from_cam = parent_from_cam_0 * (cam_c_from_cam_0)^-1 with its 11 x 11 covariance
// propagated to first order from the joint one.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "camera/estimate.h"
#include "camera/pose.h"
#include "methods/ekf_model.h"
#include "methods/method.h"

namespace calibench {

struct RigEkfOptions {
  // Per camera (intrinsics; the mount's q and p0 are camera 0's), method ekf's options.
  EkfFilterOptions camera;
  // Random walks of each axis of every relative pose (variance per second): the mount's (ROVIO's
  // 1e-8), 0.04 deg and 0.8 mm in a minute (1 sigma), a rig's thermal drift. Smaller values make
  // the filter slow to follow a knock: its memory is sqrt(1 / (q I)), I the information rate of
  // the relative rotation (~2e6 rad^-2/s in the rig scenarios: 7 s at 1e-8, 70 s at 1e-10, which
  // leaves a 0.3 deg step of configs/dynamic/rig_step.yaml unabsorbed by the end of its run).
  double q_rel_rotation_rad2_s = 1e-8;
  double q_rel_translation_m2_s = 1e-8;
  // Initial standard deviations of each axis of every relative pose about the start.
  double p0_rel_rotation_deg = 1.0;
  double p0_rel_translation_m = 0.05;

  // Visits camera's options (method ekf's keys), then the relative pose's.
  void Visit(OptionVisitor* v);
  bool Check(std::string* why) const;
};

// What a run over synchronised frames did (RunRigEkf).
struct RigEkfSummary {
  int updates = 0;  // Instants that updated the filter.
  int skipped = 0;  // Instants without corners, or degenerate (information not positive definite).
};

class RigEkf {
 public:
  static constexpr int kCameraStates = CameraEstimate::kCovarianceSize;  // 11.

  // Starts the filter from every camera's estimate (header comment). False with *why for fewer
  // than 2 cameras, a start without a camera, or options that fail Check.
  bool Start(const std::vector<CameraEstimate>& starts, const RigEkfOptions& options,
             std::string* why);

  int NumCameras() const { return static_cast<int>(lenses_.size()); }
  int NumStates() const { return kCameraStates * NumCameras(); }
  const Eigen::VectorXd& State() const { return x_; }
  const Eigen::MatrixXd& Covariance() const { return p_; }

  // The random walk over dt_s >= 0 seconds.
  void Predict(double dt_s);
  // One synchronised instant: views_by_camera[c] is camera c's frame (x_bar in the parent frame
  // and measured pixels; null or empty: nothing seen). False, with the state and covariance as
  // they were, when no corner was seen or the information is not positive definite.
  bool Update(const std::vector<const View*>& views_by_camera);

  // cam_c_from_cam_0 (c >= 1) and the covariance of its error [dtheta_c (rad), t_c (m)].
  Rigid3 CamFromCam0(int c) const;
  Eigen::Matrix<double, 6, 6> CamFromCam0Covariance(int c) const;
  // Camera c's estimate (header comment); camera 0's is method ekf's.
  CameraEstimate Estimate(int c) const;

 private:
  // The pixel of `point_in_parent` in camera c, T = double or Jet over the local states
  // [intrinsics_c (5), dtheta_0 (3), x_C (3), dtheta_c (3), t_c (3)] (camera 0: the first 11).
  template <typename T>
  bool Project(int c, const T* local, const Eigen::Vector3d& point_in_parent, T* pixel) const;
  // The global index of camera c's local state j.
  int GlobalIndex(int c, int j) const;

  RigEkfOptions options_;
  std::vector<CameraIntrinsics> lenses_;       // Each camera's start: its distortion stays fixed.
  Eigen::Matrix3d r_c_nominal_;                // Camera 0's mount.
  std::vector<Eigen::Matrix3d> r_c0_nominal_;  // Per camera (camera 0's: the identity).
  Eigen::VectorXd x_, q_;
  Eigen::MatrixXd p_;
  std::vector<int> free_;  // The estimated states (phi's only with estimate_skew).
};

// Runs `filter` (started) on synchronised frames: frames_by_camera[c] is camera c's FrameSet
// (methods/method.h), every camera with the same frame times. Every instant after after_s is a
// Predict over the time since the last one (or since after_s) and an Update; on_update(t) (may
// be empty) is called after every successful update. False with *why when the cameras' frames
// are not synchronised (their counts or times differ by more than 1 us).
bool RunRigEkf(const std::vector<const FrameSet*>& frames_by_camera, double after_s, RigEkf* filter,
               const std::function<void(double t_s)>& on_update, RigEkfSummary* summary,
               std::string* why);

}  // namespace calibench
