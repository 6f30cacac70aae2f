// The constant extrinsic parent_from_cam of a camera from per-view board poses, the two ways a
// planar-target calibration (batch/zhang.h) can give it. Both take, per view v, the board pose in
// the camera cam_from_board_v (from the calibration) and what is known of the board:
//
//   averaging  parent_from_board_v known (a target fixed in a known place of the points frame,
//              whose motion is known): every view gives parent_from_cam_v = parent_from_board_v *
//              cam_from_board_v^-1; the estimate is their chordal L2 mean (the SO(3) projection of
//              the summed rotations) and the mean position.
//   hand-eye   only the points frame's motion P_v = parent_from_points_v is known, the board's
//              place T = points_from_board in it is not. With C_v = cam_from_board_v = X^-1 P_v T
//              and X = parent_from_cam, every pair of views i < j gives AX = XB with
//              A = P_j P_i^-1 and B = C_j C_i^-1 (T cancels). Moving camera (eye-in-hand): P_v =
//              body_from_world, X = body_from_cam; fixed camera (eye-to-hand): P_v =
//              world_from_body, X = world_from_cam.
//
// Hand-eye solves Tsai and Lenz's two linear steps on all pairs, the rotation without Tsai's
// singularity. Rotation: with unit quaternions, R_A R_X = R_X R_B is q_A q_X - q_X q_B = 0, four
// linear equations in q_X per pair,
//     [ w_A - w_B    -(a - b)^T                    ] q_X = 0    (q_A = (w_A, a), q_B = (w_B, b)),
//     [ a - b        (w_A - w_B) I + Hat(a + b)    ]
// with q_A, q_B taken with w >= 0 (a rotation and its conjugate B = X^-1 A X share w = cos(turn/2),
// so this pairs their signs). q_X is the unit vector minimising the stacked residual: the right
// singular vector of the smallest singular value. Tsai's own step solves the vector part for
// v_X / w_X = tan(angle/2) axis (his modified Rodrigues vector, q_X = (w_X, v_X)), infinite at a
// half-turn X (the rig's R_C: it returned X pi off with no error). This homogeneous form has no
// singular X, is exact on exact poses at any angle, weighs each pair by ~ sin(turn/2) as Tsai's
// did, and does not depend on the frames the poses are written in (re-expressing the parent or the
// camera frame by a rotation S multiplies every pair's residual by the unit quaternion q_S: the
// answer turns with it). Pairs turning more than kHandEyeMaxPairTurnDeg are left out: at
// w_A ~ 0 noise would decide the sign pairing. Translation (Tsai's step): (R_A - I) t_X =
// R_X t_B - t_A, stacked over the pairs, by least squares (column-pivoted QR). Both steps need
// relative rotations about two non-parallel axes: a single-axis motion is refused.
#pragma once

#include <string>
#include <vector>

#include "camera/pose.h"

namespace calibench {

// Chordal L2 mean of the rotations and mean of the translations; `poses` must not be empty.
Rigid3 AveragePoses(const std::vector<Rigid3>& poses);

// Hand-eye calibration (Tsai and Lenz's equations, rotation by unit quaternion: see above) from
// the views of one board: parent_from_points[v] and cam_from_target[v] (target = that board), the
// same views in the same order. False with *why for lists of different lengths, fewer than 3
// views, a non-finite pose, a degenerate motion (single-axis or none; or too few pairs of views
// turning at most kHandEyeMaxPairTurnDeg to fix the rotation) or a non-finite result.
constexpr double kHandEyeMaxPairTurnDeg = 175.0;
bool HandEyeTsai(const std::vector<Rigid3>& parent_from_points,
                 const std::vector<Rigid3>& cam_from_target, Rigid3* parent_from_cam,
                 std::string* why);

}  // namespace calibench
