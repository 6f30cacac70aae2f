// The constant extrinsic parent_from_cam of a camera from per-view board poses, the two ways a
// planar-target calibration (batch/zhang.h) can give it. Both take, per view v, the board pose in
// the camera cam_from_board_v (from the calibration) and what is known of the board:
//
//   averaging  parent_from_board_v known (a target fixed in a known place of the points frame,
//              whose motion is known): every view gives parent_from_cam_v = parent_from_board_v *
//              cam_from_board_v^-1; the estimate is their chordal L2 mean (the SO(3) projection of
//              the summed rotations) and the mean position.
//   hand-eye   only the points frame's motion parent_from_points_v is known, the board's place in
//   it
//              is not: AX = XB, solved by cv::calibrateHandEye (Tsai). Moving camera (eye-in-hand):
//              gripper = body, base = world, target = a board fixed in W, X = body_from_cam. Fixed
//              camera (eye-to-hand): base2gripper = body_from_world is passed as the gripper poses,
//              X = world_from_cam. Either way X = parent_from_cam. Tsai's method needs relative
//              rotations about two non-parallel axes: a single-axis motion is refused.
#pragma once

#include <string>
#include <vector>

#include "core/pose.h"

namespace calibench {

// Chordal L2 mean of the rotations and mean of the translations; `poses` must not be empty.
Rigid3 AveragePoses(const std::vector<Rigid3>& poses);

// Hand-eye calibration (Tsai) from the views of one board: parent_from_points[v] and
// cam_from_target[v] (target = that board). False with *why for fewer than 3 views, a degenerate
// (single-axis) motion or an OpenCV failure.
bool HandEyeTsai(const std::vector<Rigid3>& parent_from_points,
                 const std::vector<Rigid3>& cam_from_target, Rigid3* parent_from_cam,
                 std::string* why);

}  // namespace calibench
