// The stereo calibration a user would run with OpenCV, as the rig solve's (batch/rig_refine.h)
// baseline: cv::stereoCalibrate for two radtan cameras, cv::fisheye::stereoCalibrate for two
// equidistant (pinhole-equi) cameras, on the same corners RefineRig gets.
//
// Data: the frames both cameras saw entirely, i.e. whose two views hold the same corners (matched
// by equal board coordinates: one target); any other frame is skipped (counted in the message).
// OpenCV needs one object point list per frame for both images, and its checkerboard detectors
// give whole boards. Intrinsics start from the given rig's (CALIB_USE_INTRINSIC_GUESS), or are
// held there (CALIB_FIX_INTRINSIC, `fix_intrinsics`). OpenCV applies one lens model to both
// cameras (the flags, as batch/zhang.cc chooses them for a radtan model) and fixes the skew
// (phi = 90 degrees). The other families (unified, eucm, double-sphere) are refused.
//
// Convention (camera/rig.h): OpenCV's R, T map camera 0's frame into camera 1's, p_cam1 = R p_cam0
// + T: they are camera 1's cam_from_rig (rotation R, translation T, in the target's unit).
// rms_reproj_px is OpenCV's returned figure: the RMS over both cameras' corners of the
// reprojection error's Euclidean length.
#pragma once

#include <string>
#include <vector>

#include "camera/rig.h"
#include "util/status.h"

namespace calibench {

struct StereoOpenCvOptions {
  // One model for both cameras: pinhole, pinhole-k2, pinhole-radtan4, pinhole-radtan5 (radtan:
  // cv::stereoCalibrate) or pinhole-equi (cv::fisheye::stereoCalibrate, every k1..k4 free).
  LensModel model = LensModel::kPinholeRadTan4;
  // Keep both cameras' intrinsics as given (CALIB_FIX_INTRINSIC): only R, T are estimated.
  bool fix_intrinsics = false;
  int max_iterations = 100;  // OpenCV's Levenberg-Marquardt (its default is 30).
  bool Check(std::string* why) const;
};

struct StereoOpenCvResult : MethodSummary {
  CameraRig rig;                 // Both cameras' intrinsics; camera 1's cam_from_rig = (R, T).
  double rms_reproj_px = 0.0;    // OpenCV's figure (header comment).
  std::vector<int> used_frames;  // Indices into the frames.
  int num_points = 0;            // Corners per camera over the used frames.
};

// `initial` has exactly two cameras with intrinsics of the model's family (the start) and image
// sizes (OpenCV's imageSize: camera 0's); its cam_from_rig are ignored.
StereoOpenCvResult CalibrateStereoOpenCv(const std::vector<RigFrame>& frames,
                                         const CameraRig& initial,
                                         const StereoOpenCvOptions& options);

}  // namespace calibench
