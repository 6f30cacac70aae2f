// Calibrating a camera rig (camera/rig.h) from synchronised images of a target: the whole of
// `calibench calibrate --images SRC --images SRC ...` but its flags and files.
//
//   1. Each camera alone, as `calibrate --images` calibrates one camera (calibrate_camera.h
//      CalibrateImages on that camera's images: detection, the start, ceres, the corners re-fitted
//      through the lens; its lens model given, or chosen per camera).
//   2. The rig's start (batch/rig_refine.h InitRigExtrinsics): relative poses of the cameras that
//      saw a frame together, robustly averaged, chained along a maximum spanning tree weighted by
//      the corners two cameras shared; a camera graph in pieces is refused naming the cameras cut
//      off from camera 0.
//   3. One joint refinement of every intrinsic, every cam_from_rig and one board pose per frame
//      (RefineRig), with the covariance of the baseline and of the relative rotation.
//   4. Checks a user reads: the epipolar error of the corners each pair of cameras saw at once
//      (ComputeEpipolarErrors), and the frames the rig cannot explain: a camera's view fitted by
//      the joint solve more than kDisagreeFactor times (and kDisagreeMinPx) worse than by its
//      camera alone (a camera that moved in its mount, frames not taken at the same instant).
// With a given rig (`--init` a camchain) the start is that rig; evaluate_only keeps every
// intrinsic and every cam_from_rig fixed and moves only the board poses: the reprojection and
// epipolar errors of a given rig on new images.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "batch/jackknife.h"
#include "batch/rig_refine.h"
#include "calib/calibrate_camera.h"
#include "camera/rig.h"

namespace calibench {

// One camera's images: the folder that holds them and, per frame of the rig, the file name within
// it (empty: this camera has no image of that frame). Frames are paired by the caller
// (calib/rig_images.h); files_by_frame has one entry per frame for every camera.
struct RigCameraImages {
  std::string source;  // As the user gave it (a folder or a quoted glob): names the camera.
  std::string dir;
  std::vector<std::string> files_by_frame;
};

struct CalibrateRigOptions {
  // One model for every camera (size 1) or one per camera. select_model: each camera's model is
  // chosen among the candidates (model_select.h) instead.
  std::vector<LensModel> models = {LensModel::kPinholeK2};
  bool select_model = false;
  bool estimate_skew = false;
  std::optional<CameraRig> init;  // A given rig: the start instead of the per-camera calibrations.
  std::string init_path;          // Its file, for the report.
  bool evaluate_only = false;     // With init: only the board poses move.
  int corner_iterations = 4;      // Per camera, as CalibrateOptions::corner_iterations.
  // The rig's leave-one-frame-out std of each camera's pose in the rig (batch/jackknife.h
  // JackknifeRig) beside the formal one; kAuto: with kJackknifeAutoMaxViews frames or fewer. The
  // cameras calibrated alone (step 1) run none: the joint solve supersedes them.
  CalibrateOptions::Jackknife jackknife = CalibrateOptions::Jackknife::kAuto;
  // False with *why: an empty model list, evaluate_only without init, select_model with init or
  // with a model list, negative corner_iterations. The model list's length against the number of
  // cameras is checked by CalibrateRigImages (it knows the cameras).
  bool Check(std::string* why) const;
};

// A frame's view whose joint-solve RMS exceeds kDisagreeFactor times its camera-alone RMS and
// exceeds it by kDisagreeMinPx: well-synchronised frames of a rigid rig fit about as well jointly
// as alone (the rig only adds 6 parameters per camera), so a view 2x and 0.5 px worse is one the
// rig cannot explain.
constexpr double kDisagreeFactor = 2.0;
constexpr double kDisagreeMinPx = 0.5;

struct RigFrameDisagreement {
  int frame = 0, camera = 0;
  double joint_rms_px = 0.0, alone_rms_px = 0.0;
};

struct CalibrateRigResult {
  // kBadImages: a camera's images show no target (message names its source); kBadInit: the given
  // rig does not fit (camera count, image sizes); kDisconnected: the camera graph is in pieces
  // (message names the cameras cut off); kFailed: no usable calibration (message says why).
  enum class Status { kOk, kBadImages, kBadInit, kDisconnected, kFailed };
  Status status = Status::kFailed;
  std::string message;
  std::vector<CalibrateResult> cameras;  // Each camera alone (step 1).
  std::vector<std::string> frame_names;  // Per frame (the key the images were paired by).
  std::vector<RigFrame> frames;          // The views of each frame, per camera.
  // [frame][camera]: the index of that view in cameras[camera].data.views; -1: none.
  std::vector<std::vector<int>> view_of_frame;
  RigInitSummary init;  // The spanning tree (step 2).
  RigRefineResult rig;  // The joint solve (step 3); rig.rig is the calibration.
  std::optional<RigJackknifeResult> jackknife;  // When computed (CalibrateRigOptions::jackknife).
  std::vector<EpipolarErrors> epipolar;         // Per pair of cameras that shared a corner.
  std::vector<RigFrameDisagreement> disagreements;
  // cam_overlaps as Kalibr writes it: per camera, the cameras it shared a frame with.
  std::vector<std::vector<int>> overlaps;
  bool evaluated = false;  // evaluate_only.
  bool IsUsable() const { return status == Status::kOk; }
};

// The rig of `cameras`' images of `target` (header comment). `images`: how each camera's corners
// are found (threads, refinement), as for one camera; its files are set per camera here.
CalibrateRigResult CalibrateRigImages(const std::vector<RigCameraImages>& cameras,
                                      const CalibrationTarget& target,
                                      const ImagePointOptions& images,
                                      const CalibrateRigOptions& options,
                                      std::ostream* log = nullptr);

// The same from points: each camera's views (PointData, e.g. synthetic, or a point file per
// camera) and, per frame, which view of each camera it holds.
struct RigPointData {
  std::vector<PointData> cameras;
  std::vector<std::vector<int>> view_of_frame;  // [frame][camera]: view index, -1 none.
  std::vector<std::string> frame_names;         // Per frame; empty: "frame <index>".
  std::vector<std::string> camera_names;        // Per camera; empty: "cam<index>".
};
CalibrateRigResult CalibrateRigPoints(const RigPointData& data, const CalibrateRigOptions& options);
// RigPointData of frames given as RigFrame (e.g. sim/rig_frames.h MakeRigFrames): each camera's
// non-empty views in frame order, its image size and name from `rig`.
RigPointData RigPointDataFromFrames(const std::vector<RigFrame>& frames, const CameraRig& rig);

// What `calibrate` prints for a rig: per camera its model, views and RMS; per camera c >= 1 its
// baseline +- std (mm, the target's unit x 1000), relative rotation +- std (deg per axis), centre
// in the rig frame; the epipolar RMS per pair; the frames that disagree; the spanning tree. Fixed
// precision (the same rig prints the same bytes).
std::string FormatRigReport(const CalibrateRigResult& result);

}  // namespace calibench
