// The part of the frame detector that Kalibr's corner squares need (frame_detector.h, "Grids with
// corner squares"); FrameDetector's FindTagsAmongSquares and SquaresNear are defined in
// corner_squares.cc beside it.
#pragma once

#include "detect/apriltag_detector.h"
#include "sim/render.h"

namespace calibench {

// The saddle point of each corner's X-junction (cv::cornerSubPix) in a window scaled to the corner
// squares (square_fraction: a square's edge over the tag's); a corner that moves 1 px or more
// keeps its edge-fit value.
void RefineXJunctions(const GrayImageView& image, double square_fraction, TagDetection* tag);

}  // namespace calibench
