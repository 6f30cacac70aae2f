// The pose of a board in one view when the intrinsics are known (perspective-n-point): the start
// of `calibrate --init FILE`, which refines a given calibration or evaluates it on new images.
//
// The view's pixels are first mapped through the known lens to normalised image coordinates
// (A^-1, then UndistortNormalized: every lens family of core/camera.h), so the problem is a
// pinhole PnP with K = I and no distortion: cv::solvePnP with SOLVEPNP_IPPE for a planar board
// (z = 0 in the board frame), SOLVEPNP_ITERATIVE (from the DLT) otherwise, then Levenberg-Marquardt
// on the normalised reprojection error (cv::solvePnPRefineLM).
#pragma once

#include <string>

#include "core/camera.h"
#include "core/pose.h"
#include "core/view.h"

namespace calibench {

// cam_from_board of `view` (points in the board frame) seen through `intrinsics`. False with *why
// for fewer than 4 points (6 off-plane), a pixel outside the lens' valid region or an OpenCV
// failure.
bool BoardPoseFromIntrinsics(const View& view, const CameraIntrinsics& intrinsics,
                             Rigid3* cam_from_board, std::string* why);

}  // namespace calibench
