// Calibration points from a folder of images: `calibench calibrate --images DIR --target T.yaml`.
//
// Every PNG / JPG / JPEG / TIF / TIFF / BMP file of DIR (sorted by name) is read as 8-bit gray. The
// target (target_io.h) is found per image:
//   checkerboard: detect/chessboard.h. Corner (r, c) of the targetCols x targetRows inner corners
//       is at (c * colSpacing, r * rowSpacing, 0);
//   aprilgrid: AprilTag 3 + edge-fit refinement + matching (detect/frame_detector.h).
// Pixels use calibench's convention (camera.h), which is OpenCV's. An image that cannot be read,
// has another size than the first, or shows too little of the target is listed with the reason
// and skipped, never fatal; no usable image at all is an error.
#pragma once

#include <string>
#include <vector>

#include "bench/app/points_io.h"
#include "bench/config/target_io.h"

namespace calibench {

struct ImageResult {
  std::string file;
  bool used = false;
  int points = 0;      // Target points found.
  std::string reason;  // Why it was skipped, or how the target was found.
};

struct ImageFolderReport {
  std::vector<ImageResult> images;  // One per image file, in name order.
  int used = 0;
  long tags_detected = 0, unknown_tags = 0;  // aprilgrid only.
  long tags_possible = 0;  // aprilgrid: the grid's tags x readable images of the right size.
  // aprilgrid: tags_detected / tags_possible (0 when nothing was readable). A rate far below the
  // share of the grid the images show means the target YAML does not match (tagFamily,
  // codeOffset, tagCols / tagRows).
  double DetectionRate() const {
    return tags_possible > 0 ? static_cast<double>(tags_detected) / tags_possible : 0.0;
  }
};
// Below this detection rate FormatImageReport and LoadImagePoints's error say so.
constexpr double kLowDetectionRate = 0.5;

// Views (target points in the board frame, their pixels) of every usable image; data->views[i]
// comes from report->images[used_index[i]]. Returns false with *why naming the folder or target
// when the folder cannot be listed, holds no image, or no image shows the target.
bool LoadImagePoints(const std::string& dir, const CalibrationTarget& target, PointData* data,
                     ImageFolderReport* report, std::vector<int>* used_index, std::string* why);

}  // namespace calibench
