// Chessboard (checkerboard) corner detection: the inner corners of a cols x rows pattern, in
// calibench's pixel convention (camera/camera.h: pixel centres at integers, which is OpenCV's).
//
//   1. cv::findChessboardCorners (adaptive threshold, normalised image; with its fast check, which
//      rejects in milliseconds an image it would search for seconds in vain, e.g. a fisheye's bent
//      board: the same boards and corners on the bundled and shared sets), refined by
//      cv::cornerSubPix with a 5 x 5 half-window (11 x 11 px) and 30 iterations / 0.1 px, as
//      OpenCV's own calibration sample does (X-junctions: cornerSubPix's model fits them);
//   2. if that finds nothing, cv::findChessboardCornersSB (sub-pixel by itself).
// With sector_based_first, 2 is tried before 1: on a fisheye's bent boards the classic search often
// fails after seconds where the sector-based one succeeds in tens of milliseconds.
// Corner (r, c), r < rows, c < cols, is returned at index r * cols + c, in one order whichever
// detector found it: rows and columns turn as the image's x and y (the board seen from the front),
// and, when cols + rows is odd, the square between corners (0, 0) and (1, 1) is dark (a half turn
// would make it light); a board with cols + rows even keeps its half-turn ambiguity. The cameras
// of a rig then agree on the board frame.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sim/render.h"

namespace calibench {

struct ChessboardOptions {
  int cols = 9, rows = 6;           // Inner corners per row and per column.
  bool sector_based_first = false;  // Header comment.
  bool Check(std::string* why) const;
};

// The corners of the pattern in `gray`, or false when the whole pattern is not found. *how names
// the detector that found it.
bool FindChessboardCorners(const GrayImageView& gray, const ChessboardOptions& options,
                           std::vector<Eigen::Vector2d>* corners, std::string* how);

}  // namespace calibench
