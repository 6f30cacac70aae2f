// The pose of a board in one view when the intrinsics are known (perspective-n-point): the start
// of `calibrate --init FILE`, which refines a given calibration or evaluates it on new images, and
// of every view in the wide start (batch/wide_init.h).
//
// The view's pixels are lifted through the known lens to unit rays (UnprojectToRay: every lens
// family of camera/camera.h, past 90 degrees from the axis too, where X/Z does not exist). The rays
// are turned by a rotation Q (exact) that takes their mean direction to the axis: a board then
// spans less than 180 degrees about it, the turned rays have z > 0, and their (X/Z, Y/Z) make a
// pinhole PnP with K = I and no distortion: cv::solvePnP with SOLVEPNP_IPPE for a planar board
// (z = 0 in the board frame), SOLVEPNP_ITERATIVE (from the DLT) otherwise, then Levenberg-Marquardt
// on that plane's reprojection error (cv::solvePnPRefineLM). The pose is turned back:
//     cam_from_board = Q^T * cam'_from_board.
#pragma once

#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/pose.h"
#include "camera/view.h"

namespace calibench {

// Sum over the view's points of |Project(intrinsics, cam_from_board * point) - pixel|^2 [px^2],
// the one reprojection sum of the batch code. False (and *sum_sq_px2 = +inf) when a point does not
// project (outside the lens' valid region: behind the camera for radtan and equidistant).
bool ViewSquaredErrorPx2(const View& view, const CameraIntrinsics& intrinsics,
                         const Rigid3& cam_from_board, double* sum_sq_px2);

struct BoardPoseOptions {
  // Levenberg-Marquardt after IPPE / the DLT (cv::solvePnPRefineLM). Without it, a planar pose is
  // IPPE's (exact for exact rays), 5x faster: what the wide start scores its candidates with.
  bool refine = true;
};

// cam_from_board of `view` (points in the board frame) seen through `intrinsics`. False with *why
// for fewer than 4 points (6 off-plane), collinear points or all but one collinear (see
// BoardPoseFromRays), a pixel outside the lens' valid region, an OpenCV failure or a non-finite
// pose.
bool BoardPoseFromIntrinsics(const View& view, const CameraIntrinsics& intrinsics,
                             Rigid3* cam_from_board, std::string* why,
                             const BoardPoseOptions& options = {});

// cam_from_board of a view from the unit rays of its points (rays[i] for view.points[i]), as the
// header comment says (BoardPoseFromIntrinsics lifts the pixels, then calls it). False with *why
// for too few points, a non-finite point, collinear points, a board spanning more than
// kMaxBoardSpanDeg about its mean ray, an OpenCV failure, or a non-finite pose (solvePnP can
// "succeed" with NaN). Collinear points leave the turn about their line free, and all but one on a
// line leave the homography of a planar set (IPPE's, and SOLVEPNP_ITERATIVE's for coplanar
// points) undetermined; both are refused. With l1 <= l2 the two largest eigenvalues of a point
// set's scatter matrix about its centroid (spreads squared), it counts as collinear unless
// sqrt(l1 / l2) > kMinPointSpreadRatio: its points leave their best-fitting line by more than
// 1e-6 of their extent along it. Checked for the whole set and for it without each point in turn
// (one rank-one downdate each). Board coordinates are design values: rounding leaves ~1e-16 where
// a line was meant, and a board with two rows of points is at ~1e-2 or more.
constexpr double kMaxBoardSpanDeg = 176.0;
constexpr double kMinPointSpreadRatio = 1e-6;
bool BoardPoseFromRays(const View& view, const std::vector<Eigen::Vector3d>& rays,
                       Rigid3* cam_from_board, std::string* why,
                       const BoardPoseOptions& options = {});

}  // namespace calibench
