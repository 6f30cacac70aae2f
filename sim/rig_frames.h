// Synthetic ground truth for camera rigs (camera/rig.h): synchronised frames of one planar board
// seen by every camera of a rig at the same instant, as the batch rig solve consumes them
// (camera/rig.h RigFrame, batch/rig_refine.h), and the same scenes as images (RenderRigFrame).
//
// Each frame places the board in front of one camera chosen at random (the "anchor" of the frame,
// uniform over the cameras, or over `anchor_cameras` when given): RandomFacingBoardPose of that
// camera (off-axis angle uniform in [0, max_off_axis_deg], distance uniform in [near_m, far_m],
// tilt up to max_tilt_deg), so that rig_from_board = cam_from_rig_anchor^-1 * cam_from_board.
// Every camera then sees what its lens images inside its image: a camera keeps its view when
// `whole_board` and every corner is inside (checkerboard detectors need the whole pattern) or, if
// not whole_board, when at least min_visible_fraction of the corners are (the others dropped:
// partial boards, as AprilGrids give). A frame seen by fewer than min_cameras cameras is redrawn.
// A camera behind the board's plane (its back side) sees nothing, and so do points where the
// camera's image folds over (CameraIntrinsics::DistortionIsMonotoneAlong).
// Cameras whose fields never meet (a camera linked to camera 0 only through another) arise from the
// rig's geometry alone: the board is where its anchor camera looks.
//
// Draw order per frame attempt (determinism: one Rng, seeded by the caller from (seed, trial)):
// the anchor, then RandomFacingBoardPose's draws, then each camera's pixel noise in camera order.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "camera/rig.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {

struct RigFramesOptions {
  int rows = 6, cols = 8;   // Corners of the board (BoardPoints).
  double spacing_m = 0.04;  // Corner pitch.
  int num_frames = 24;
  double max_off_axis_deg = 25.0;         // The board centre's angle from the anchor camera's axis.
  FacingPoseRange range{35.0, 0.5, 0.8};  // Tilt (deg) and distance (m) of the board centre.
  bool whole_board = true;
  double min_visible_fraction = 0.5;  // When !whole_board; and at least 8 corners.
  int min_cameras = 2;                // Cameras that must see a frame.
  std::vector<int> anchor_cameras;    // Empty: every camera.
  double pixel_sigma_px = 0.0;        // Gaussian noise on u and v.
  double edge_margin_px = 5.0;        // Corners closer to the image border count as outside.
  int max_attempts = 0;               // Frame draws before giving up; 0: 50 * num_frames.
  bool Check(std::string* why) const;
};

struct SyntheticRigFrames {
  std::vector<RigFrame> frames;        // Board-frame points, noisy pixels.
  std::vector<Rigid3> rig_from_board;  // Truth, one per frame.
  std::vector<int> anchor;             // Each frame's anchor camera.
};

// `rig` must pass Check() and give every camera an image size. Fewer frames than asked when the
// attempts ran out (the caller checks frames.size()).
SyntheticRigFrames MakeRigFrames(const CameraRig& rig, const RigFramesOptions& options, Rng* rng);

}  // namespace calibench
