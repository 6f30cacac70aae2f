// The pose of a board in one view when the intrinsics are known (perspective-n-point): the start
// of `calibrate --init FILE`, which refines a given calibration or evaluates it on new images.
//
// The view's pixels are first mapped through the known lens to normalised image coordinates
// (A^-1, then UndistortNormalized: every lens family of core/camera.h), so the problem is a
// pinhole PnP with K = I and no distortion: cv::solvePnP with SOLVEPNP_IPPE for a planar board
// (z = 0 in the board frame), SOLVEPNP_ITERATIVE (from the DLT) otherwise, then Levenberg-Marquardt
// on the normalised reprojection error (cv::solvePnPRefineLM).
//
// EquidistantFocalScan: a start for a fisheye calibration that needs no closed form. Most fisheye
// lenses are close to the ideal equidistant r = f theta: with k1..k4 = 0 and the principal point at
// the image centre, every focal length of a log-spaced scan gets each view's pose by the PnP above,
// and the one with the least reprojection error wins (ceres then frees everything). It is what
// `calibrate --model pinhole-equi` falls back to when cv::fisheye::calibrate fails, as it does on
// partial boards far off axis.
#pragma once

#include <string>

#include "core/camera.h"
#include "core/pose.h"
#include "core/view.h"

namespace calibench {

// Sum over the view's points of |Project(intrinsics, cam_from_board * point) - pixel|^2 [px^2],
// the one reprojection sum of the batch code. False (and *sum_sq_px2 = +inf) when a point is not
// in front of the camera.
bool ViewSquaredErrorPx2(const View& view, const CameraIntrinsics& intrinsics,
                         const Rigid3& cam_from_board, double* sum_sq_px2);

// cam_from_board of `view` (points in the board frame) seen through `intrinsics`. False with *why
// for fewer than 4 points (6 off-plane), a pixel outside the lens' valid region or an OpenCV
// failure.
bool BoardPoseFromIntrinsics(const View& view, const CameraIntrinsics& intrinsics,
                             Rigid3* cam_from_board, std::string* why);

struct FocalScanResult {
  CameraIntrinsics intrinsics;         // Equidistant, k = 0, centre of the image.
  std::vector<Rigid3> cam_from_board;  // One per view (identity where its PnP failed).
  double rms_reproj_px = 0.0;          // Over the views whose pose was found.
  int views_posed = 0;
};

struct FocalScanOptions {
  int image_width = 0, image_height = 0;
  double min_focal_per_width = 0.1;  // Scan f from 0.1 W ..
  double max_focal_per_width = 2.0;  // .. to 2 W (a 180-degree lens has f ~ W / pi).
  int steps = 80;                    // Log-spaced.
  bool Check(std::string* why) const;
};

bool EquidistantFocalScan(const std::vector<View>& views, const FocalScanOptions& options,
                          FocalScanResult* result, std::string* why);

}  // namespace calibench
