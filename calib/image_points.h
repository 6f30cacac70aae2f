// Calibration points from a folder of images: `calibench calibrate --images DIR --target T.yaml`.
//
// Every PNG / JPG / JPEG / TIF / TIFF / BMP file of DIR (sorted by name) is read as 8-bit gray
// (ReadGray8: 16-bit images are scaled by their own percentiles). The target (target_io.h) is
// found per image:
//   checkerboard: detect/chessboard.h (cornerSubPix); given a camera (ImagePointOptions::camera),
//       each corner is then refined as an X-junction through its lens (detect/x_junction.h) and a
//       corner whose refinement fails is left out. Corner (r, c) of the targetCols x targetRows
//       inner corners is at (c * colSpacing, r * rowSpacing, 0);
//   aprilgrid: AprilTag 3 with the target's black border + edge-fit refinement (+ the corner
//       squares' handling) + matching (detect/frame_detector.h, ImageDetectorOptions).
// Pixels use calibench's convention (camera.h), which is OpenCV's. An image that cannot be read,
// has another size than the first, or shows too little of the target is listed with the reason
// and skipped, never fatal; no usable image at all is an error.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "calib/calibration_target.h"
#include "calib/point_data.h"
#include "detect/frame_detector.h"
#include "sim/render.h"

namespace calibench {

// What the detector found in each image of a folder (AprilTag 3's tags, FrameDetector::FindTags;
// a checkerboard's corners, detect/chessboard.h), kept by a calibration that re-fits the corners
// through each new estimate of its camera: the images are read again, the detector does not run
// again.
struct ImageDetectionCache {
  bool filled = false;
  // What it was filled from: the folder, its files, the target (its YAML text) and, for a
  // checkerboard, whether the sector-based detector went first (a wide lens); reused only for the
  // same.
  std::string source;
  // FindTags used the camera (FrameDetector::FindingUsesCamera: corner squares painted out
  // through a distorting lens, perspective views of a wide one): it then finds more tags than
  // without one, and is not reused by a pass that has a camera when it was filled without.
  bool found_through_lens = false;
  std::vector<FoundTags> per_image;  // By the folder's image order; empty for unreadable images.
  // checkerboard: each image's corners as detect/chessboard.h found them (row-major; empty: not
  // found or unreadable), by the folder's image order.
  std::vector<std::vector<Eigen::Vector2d>> checkerboard_corners;
};

// How the corners of a folder of images are found.
struct ImagePointOptions {
  LensFamily lens = LensFamily::kRadTan;  // The family the images will be calibrated with.
  // A calibration of these images: the photometric fit is drawn through its lens (lens-aware);
  // a checkerboard's corners are refined as X-junctions through it (detect/x_junction.h).
  std::optional<CameraIntrinsics> camera;
  // nullopt: the photometric fit (the edge fit with curved edges for a fisheye without camera).
  std::optional<CornerRefinement> refinement;
  // Grid tags AprilTag 3 did not decode are fitted where their neighbours put them
  // (FrameDetectorOptions::predict_missing_tags; photometric refinement only).
  bool predict_missing_tags = true;
  // In / out: filled by the first call that gets it, reused by later ones on the same folder
  // (the same files) and target.
  ImageDetectionCache* detection_cache = nullptr;
  // Only these images of the folder (file names within it, e.g. a glob's matches, one camera's
  // images of a rig); empty: every image of the folder.
  std::vector<std::string> files = {};
  // Images are read and detected in parallel on this many threads (<= 0: every core); the
  // result does not depend on it.
  int threads = 0;
};

// The detector options for images of an aprilgrid: the defaults (the corner squares of Kalibr's
// printed grids are the grid's: AprilGrid::corner_squares). For a wide lens (`lens` of any family
// but radtan) the edge fit takes curved edges (corner_refinement.h, curved_edges).
FrameDetectorOptions ImageDetectorOptions(const ImagePointOptions& options = {});

// True when `path` names an image calibrate reads: png, jpg, jpeg, tif, tiff or bmp, any case.
bool IsImageFile(const std::string& path);

// The image files of `dir` (IsImageFile), sorted by name. False with *why naming
// the folder when it cannot be listed or holds no image.
bool ListImageFiles(const std::string& dir, std::vector<std::string>* files, std::string* why);

// Percentiles of a 16-bit image mapped to gray 0 and 255 by ReadGray8.
constexpr double kLowPercentile = 0.1, kHighPercentile = 99.9;

// Reads `path` as 8-bit gray (colour is converted by OpenCV's luma weights). A 16-bit image (the
// TUM VI frames: 16-bit PNGs whose values fill only part of the range) is mapped linearly,
//   g8 = clamp(255 (g16 - lo) / (hi - lo)), lo, hi = its kLowPercentile / kHighPercentile,
// rounded: a linear map moves no edge (the detector's edge and corner positions are those of
// the 16-bit image up to quantisation), and the percentiles, unlike min / max, ignore a few hot
// or dead pixels. False (image emptied) when the file cannot be read or decoded, with the reason
// in *why; *note says how a 16-bit image was scaled (else empty).
bool ReadGray8(const std::string& path, GrayImage* image, std::string* why, std::string* note);

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
// `options`: how the corners are found (ImageDetectorOptions).
bool LoadImagePoints(const std::string& dir, const CalibrationTarget& target, PointData* data,
                     ImageFolderReport* report, std::vector<int>* used_index, std::string* why,
                     const ImagePointOptions& options = {});

}  // namespace calibench
