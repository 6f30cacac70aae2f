// Calibrating a camera rig (camera/rig.h) from synchronised frames of a target: the start as the
// anchors make it, then one joint maximum-likelihood refinement, and the uncertainty of what a rig
// user reads (baseline, relative rotation) with its Cramer-Rao bound.
//
// Data: RigFrame f (camera/rig.h) holds, per camera c, the View of the target camera c saw at that
// instant (points in the board frame, their pixels); an empty View = camera c missed it.
//
// Start (InitRigExtrinsics): every camera calibrated alone gives cam_from_board_{c,f} for the
// frames it saw. Two cameras that saw frame f give one measurement of cam_a_from_cam_b =
// cam_from_board_{a,f} * cam_from_board_{b,f}^-1; a pair's relative pose is their robust average
// (the chordal L2 mean of the rotations after dropping those > kInitOutlierDeg from the geodesic
// median, the median of the translations). Cameras are nodes of a graph whose edge weights are the
// corners both saw; a maximum spanning tree from camera 0 (Kalibr's and OpenCV 5's rule: the pairs
// with the most shared observations) chains the pairs into every cam_from_rig. A camera that
// shares no frame with camera 0's component is cut off: an error naming every such camera. Each
// frame's rig_from_board is then the robust average of the cameras that saw it.
//
// Refinement (RefineRig): minimises sum_{f, c, i} rho(|Project(A_c, cam_from_rig_c *
// rig_from_board_f
// * X_fci) - p_fci|^2) over every camera's free intrinsics (its lens model, optional skew), every
// cam_from_rig_c for c >= 1 (camera 0 is the rig frame: the gauge), and one rig_from_board per
// frame. Rotations are quaternion blocks (Ceres' manifold), perturbed as R' = Exp(d) R.
//
// Covariance: sigma^2 (J^T J)^-1 with the frame poses marginalised (their Schur complement), sigma
// the known pixel noise if given, else from the residuals, sigma_hat^2 = 2 cost / (m - p). From it,
// by first-order propagation: each camera's intrinsics std; each cam_from_rig_c's 6 x 6 covariance
// [d (3, rad, R' = Exp(d) R), t (3, m)]; the baseline length std (mm); the baseline direction std
// (deg: the RMS angle the unit vector c / |c| of the camera's centre in the rig, c = -R^T t,
// moves by; as the jackknife's, batch/jackknife.h); the relative rotation's
// rotation-vector std per axis (deg; camera/rig.h); each camera's projection uncertainty
// (batch/projection_uncertainty.h), its frame the average of the frames it saw. Evaluated at the
// true parameters with the true sigma (RigCovarianceAt) the same numbers are the Cramer-Rao lower
// bound.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "batch/projection_uncertainty.h"
#include "batch/refine.h"
#include "camera/rig.h"
#include "camera/view.h"
#include "util/status.h"

namespace calibench {

// Rotations of one pair's measurements farther than this from their geodesic median are dropped
// from its average (a view whose board pose flipped, a bad detection).
constexpr double kInitOutlierDeg = 5.0;

// The spanning tree the start chose: for each camera c >= 1, the camera it was chained from and
// the number of corners both saw in their shared frames (tree edge weights).
struct RigInitSummary : MethodSummary {
  std::vector<int> parent;         // parent[0] = -1.
  std::vector<int> shared_points;  // Corners both saw, with the parent (0 for camera 0).
  // Frames (per tree edge, the child's index) whose relative pose was dropped as an outlier.
  std::vector<std::vector<int>> outlier_frames;
};

// cam_from_rig of every camera, given each camera's board poses: cam_from_board[c][f] valid where
// has_pose[c][f]; *rig_from_board gets one pose per frame (identity for a frame no camera saw).
// `views` gives the weights (corners shared). The rig's intrinsics are left as given; rig->cameras
// must have one entry per camera. Fails naming the cameras cut off from camera 0, or a pair whose
// frames all disagree.
RigInitSummary InitRigExtrinsics(const std::vector<RigFrame>& frames,
                                 const std::vector<std::vector<Rigid3>>& cam_from_board,
                                 const std::vector<std::vector<bool>>& has_pose, CameraRig* rig,
                                 std::vector<Rigid3>* rig_from_board);

struct RigRefineOptions {
  // Per camera, the lens model it is refined with (its size must equal the number of cameras; a
  // camera's intrinsics must be of that model's family).
  std::vector<LensModel> models;
  bool estimate_skew = false;  // phi free for every camera; false: phi = 90 degrees.
  RobustLoss loss = RobustLoss::kNone;
  double loss_scale_px = 1.0;
  int max_iterations = 200;
  bool compute_covariance = true;
  double known_pixel_sigma_px = 0.0;  // > 0: scale the covariance by it; 0: from the residuals.
  // Keep every intrinsic at its initial value (a rig whose cameras were calibrated alone: only the
  // extrinsics and the frame poses move).
  bool fix_intrinsics = false;
  // Keep every cam_from_rig at its initial value (with fix_intrinsics: a given rig evaluated on
  // new frames, only the frame poses move).
  bool fix_extrinsics = false;
  bool Check(std::string* why) const;
};

// The uncertainty of camera c's pose in the rig (c >= 1), from RigRefineResult's covariance.
struct RigPoseUncertainty {
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // [d, t]
  double baseline_std_mm = 0.0;
  double baseline_direction_std_deg = 0.0;
  Eigen::Vector3d rotation_std_deg = Eigen::Vector3d::Zero();  // Rotation vector, per axis.
};

struct RigRefineResult : MethodSummary {
  CameraRig rig;                       // Intrinsics and cam_from_rig of every camera.
  std::vector<Rigid3> rig_from_board;  // One per frame (identity for a frame no camera saw).
  std::vector<IntrinsicsArray> intrinsics_std;  // Per camera; NaN where fixed or not computed.
  std::vector<IntrinsicsCovariance> intrinsics_covariance;  // Per camera.
  std::vector<RigPoseUncertainty> pose_uncertainty;         // Per camera ([0] all zero).
  // Per camera: Cov(z) of its projection uncertainty (batch/projection_uncertainty.h), averaged
  // over the frames it saw (rig_refine.cc, RigProjection); unset without a covariance.
  std::vector<ProjectionCovariance> projection;
  // Per camera c: the covariance of what carries camera 0's rays into camera c (its relative pose
  // in pixels, batch/projection_uncertainty.h TransferUncertaintyAt); [0] unset.
  std::vector<TransferCovariance> transfer;
  double rms_reproj_px = 0.0;                     // Over every corner of every camera.
  std::vector<double> camera_rms_px;              // Per camera.
  std::vector<std::vector<double>> frame_rms_px;  // [frame][camera]; NaN where not seen.
  double sigma_hat_px = 0.0;                      // Residual-based noise estimate (per coordinate).
  int num_points = 0;
};

RigRefineResult RefineRig(const std::vector<RigFrame>& frames, const CameraRig& initial,
                          const std::vector<Rigid3>& initial_rig_from_board,
                          const RigRefineOptions& options);

// The covariance (and RigPoseUncertainty) at the given parameters with pixel noise
// `pixel_sigma_px`, no solve: at the truth, the Cramer-Rao lower bound of every figure of
// RigRefineResult. False with *why if J^T J is rank deficient.
bool RigCovarianceAt(const std::vector<RigFrame>& frames, const CameraRig& rig,
                     const std::vector<Rigid3>& rig_from_board, const RigRefineOptions& options,
                     double pixel_sigma_px, RigRefineResult* bound, std::string* why);

// The epipolar error of a rig on the corners two cameras saw at once: a corner is shared when
// both views of a frame hold the same board point (the same target: equal coordinates). Each
// pixel is undistorted through its camera's lens to a ray; the error of a shared corner is the
// mean over both images of the distance (px: the angle off the epipolar plane of the other ray,
// times the camera's focal length fku) of the ray from the epipolar plane through the rig's
// relative pose CamFromCam(a, b). Independent of the board poses: it checks the rig alone.
struct EpipolarErrors {
  int camera_a = 0, camera_b = 1;
  double rms_px = 0.0;
  int num_points = 0;
  std::vector<double> frame_rms_px;  // Per frame; NaN where the pair shares no corner.
};
EpipolarErrors ComputeEpipolarErrors(const std::vector<RigFrame>& frames, const CameraRig& rig,
                                     int camera_a, int camera_b);

}  // namespace calibench
