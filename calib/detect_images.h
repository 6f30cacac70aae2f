// `calibench detect --images DIR --target T.yaml --out corners.csv`: the target's corners found in
// a folder of images (an AprilGrid's tags, or a checkerboard's inner corners), for inspection or
// for another calibration tool.
//
// Every image of DIR (image_points.h: ListImageFiles, ReadGray8 — 16-bit images are scaled by
// their own percentiles) goes through the detector `calibrate --images` uses (AprilTag 3 with the
// target's black border width, edge-fit refinement, Kalibr's corner squares handled, tags within
// 2 px of the image border dropped: detect/frame_detector.h, image_points.h). corners.csv has one
// row per detected corner,
//   image,tag_id,corner,u_px,v_px,crlb_px (crlb_px: the corner's Cramer-Rao std per axis from the
//   photometric fit, empty for other refinements)
// image = the file name; corner = 0..3 in Kalibr's order (bottom-left, bottom-right, top-right,
// top-left of the tag on the board, sim/target.h); for a checkerboard (detect/chessboard.h, as
// calibrate --images finds it) tag_id is empty and corner is the inner corner's index r cols + c,
// the corner at (c colSpacing, r rowSpacing) on the board; u_px, v_px in calibench's pixel
// convention, which is OpenCV's (the centre of pixel (i, j) is at (i, j)). Rows are sorted by
// image, then tag id, then corner (the CLI writes the file, atomically).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "calib/calibration_target.h"

namespace calibench {

struct ImageCorners {
  std::string file;  // File name within the folder.
  bool readable = false;
  std::string note;  // Why unreadable, or how a 16-bit image was scaled.
  // Tags found (a checkerboard: 1 when its whole pattern was found, else 0).
  int tags = 0, unknown_tags = 0, border_tags = 0, duplicate_tags = 0;
  int refused_tags = 0;         // Photometric fit refused (dropped).
  int unrefined_copy_tags = 0;  // DetectionCounts::unrefined_copy_tags (dropped).
  int predicted_tags = 0;       // Of tags: fitted where their neighbours put them (not decoded).
  int refitted_tags = 0;        // DetectionCounts::refitted_tags.
  int covered_tags = 0;         // DetectionCounts::covered_tags.
  int refused_predictions = 0;  // DetectionCounts::refused_predictions.
  std::string refused_reasons;  // "diverged 1, image_border 2" (FitFailureName), or empty.
  struct Corner {
    int tag_id = -1, corner = -1;  // tag_id -1: a checkerboard's corner.
    double u_px = 0, v_px = 0;
    double crlb_px = std::numeric_limits<double>::quiet_NaN();  // Observation::crlb_px.
  };
  std::vector<Corner> corners;  // Sorted by tag id, then corner.
};

// Detects `target` in every image of `dir`. False with *why naming the folder when it holds no
// image; unreadable images are listed, not fatal.
bool DetectImageCorners(const std::string& dir, const CalibrationTarget& target,
                        std::vector<ImageCorners>* images, std::string* why);

// One line per image: file, tags found of the grid's (a checkerboard: corners found of its
// pattern's), and the ids or notes worth knowing; then a total.
std::string FormatImageCorners(const std::vector<ImageCorners>& images,
                               const CalibrationTarget& target);

}  // namespace calibench
