// Leave-one-view-out (delete-1 jackknife) standard deviations of a per-view-pose calibration.
//
// The formal std of RefineCalibration, sigma_hat^2 (J^T J)^-1, assumes every pixel's error is
// independent and the lens model exact. Real corners are not: a view's corners share its
// blur, lighting, board flatness and the lens model's misfit there, so the errors of one view are
// correlated and the formal std shrinks as 1 / sqrt(points) when it should shrink as
// 1 / sqrt(views). On five real fisheye frames the formal std of f was measured ~9x too small
// (docs/results/detection.md, TUM VI). The jackknife measures the view-to-view spread instead:
//   theta_(i) = the calibration without view i (all N - 1 other views, started from the full fit),
//   theta_(.) = mean_i theta_(i),
//   var_jack  = (N - 1) / N * sum_i (theta_(i) - theta_(.))^2    (Efron & Stein; Quenouille),
// per intrinsic. It needs no noise model and costs N refinements (warm-started: a few iterations
// each). It is consistent for smooth estimators like this one; with very few views it is itself
// noisy (its relative error is ~sqrt(2 / (N - 1)) for the variance), and it cannot see an error
// every view shares (a wrong board spacing, a bias common to all corners).
#pragma once

#include <string>
#include <vector>

#include "batch/refine.h"
#include "batch/rig_refine.h"
#include "camera/view.h"
#include "util/status.h"

namespace calibench {

struct JackknifeOptions {
  // The full fit's options (model, skew, loss, ...). Per-view poses only; the covariance is not
  // computed for the refits.
  RefineOptions refine;
  // Fewer views than this: no jackknife (N - 1 views must still determine the camera, and below
  // ~5 the spread of N values says little).
  int min_views = 5;
  // The views' numbers in messages (e.g. their index in the caller's input); empty: 0..N-1.
  std::vector<int> view_ids;
  bool Check(std::string* why) const;
};

struct JackknifeResult : MethodSummary {
  int num_views = 0;
  // Jackknife std per raw intrinsic (IntrinsicsArray order, phi in radians); NaN where the options
  // keep the parameter fixed (FixedIntrinsics, extra_fixed_intrinsics).
  IntrinsicsArray intrinsics_std{};
  // [i]: the calibration without view i.
  std::vector<CameraIntrinsics> leave_one_out;
  // [i]: its poses of every view but i, in order (for the projection's jackknife:
  // calib/calibration_uncertainty.h).
  std::vector<std::vector<Rigid3>> leave_one_out_poses;
};

// `full` is the usable result of RefineCalibration(views, ..., options.refine) (its intrinsics and
// per-view poses start every refit). Failed (with the view and the reason) when a refit fails.
JackknifeResult JackknifeIntrinsics(const std::vector<View>& views, const RefineResult& full,
                                    const JackknifeOptions& options);

// The same for a rig (batch/rig_refine.h): leave one frame out (every camera's view of it), refit
// the joint solve from the full fit, and take the jackknife std of each camera's pose in the rig:
// the baseline length (mm), the baseline direction (the angle of each refit's unit baseline from
// their mean, deg) and the rotation vector of cam_from_rig per axis (deg), as RigPoseUncertainty
// holds the formal ones. On real corners it is the uncertainty to quote when it exceeds the
// formal one (the corners of a frame share their errors). A frame without which a camera is cut
// off from camera 0 fails the jackknife, naming the frame.
struct RigJackknifeOptions {
  RigRefineOptions refine;  // The full fit's; the covariance is not computed for the refits.
  int min_frames = 5;       // As JackknifeOptions::min_views.
  bool Check(std::string* why) const;
};

struct RigJackknifeResult : MethodSummary {
  int num_frames = 0;
  // Per camera ([0] all zero); covariance unset (zero).
  std::vector<RigPoseUncertainty> pose;
};

// `full` is the usable RefineRig(frames, ...) result (its rig and frame poses start every refit).
RigJackknifeResult JackknifeRig(const std::vector<RigFrame>& frames, const RigRefineResult& full,
                                const RigJackknifeOptions& options);

}  // namespace calibench
