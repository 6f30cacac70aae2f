// The AprilTag 3 detector (UMich C library) behind RAII, with calibench's pixel convention.
//
// Ownership (apriltag.h): the detector owns nothing we add; families are created and destroyed by
// their *_create / *_destroy pair; apriltag_detector_detect returns a zarray of detections that
// apriltag_detections_destroy frees. Each is held by a std::unique_ptr with that deleter.
//
// Pixel convention: AprilTag 3 reports corners as if pixel centres were at (i + 0.5, j + 0.5);
// calibench's (camera.h) are at (i, j). Corners are converted here, once: ours = theirs - 0.5
// (measured here: the raw offset is +0.47..+0.50 px; tests/detect checks the round trip).
// Corner order: the detector's, i.e. the tag's bitmap bottom-left, bottom-right, top-right,
// top-left — AprilGrid's order (sim/target.h).
// Border: black_border_bits = 2 decodes Kalibr's AprilGrid tags (a 2-cell black border) through a
// derived family (sim/tag_family.h AprilTagFamilyHandle); the reported corners are then those of
// the outer edge of the 2-cell border (Kalibr's tagSize square).
// One detector is not thread-safe; use one per thread.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "sim/render.h"
#include "sim/tag_family.h"

struct apriltag_detector;

namespace calibench {

struct AprilTagOptions {
  std::string family = "tag36h11";
  int black_border_bits = 1;   // 1: AprilTag 3's layout; 2: Kalibr's (tag_family.h).
  double quad_decimate = 1.0;  // 1: full resolution (decimation leaves up to 0.03 px of bias).
  double quad_sigma = 0.0;     // Gaussian blur before quad detection.
  bool refine_edges = true;
  double decode_sharpening = 0.25;
  int threads = 1;
  int max_hamming = 1;  // Bits corrected at most (2 raises false positives).
  bool Check(std::string* why) const;
};

struct TagDetection {
  int id = -1;
  int hamming = 0;
  double decision_margin = 0.0;
  std::array<Eigen::Vector2d, 4> corners;  // calibench pixel convention, detector order.
};

class AprilTagDetector {
 public:
  static std::unique_ptr<AprilTagDetector> Create(const AprilTagOptions& options, std::string* why);
  ~AprilTagDetector();
  AprilTagDetector(const AprilTagDetector&) = delete;
  AprilTagDetector& operator=(const AprilTagDetector&) = delete;

  // Detections sorted by id. The image is only read.
  std::vector<TagDetection> Detect(const GrayImage& image) const;
  // The same on a raw 8-bit buffer (e.g. a cv::Mat's data, zero copy): row stride in bytes.
  std::vector<TagDetection> Detect(const uint8_t* pixels, int width, int height, int stride) const;

 private:
  AprilTagDetector() = default;
  struct DetectorDeleter {
    void operator()(apriltag_detector* d) const;
  };
  std::unique_ptr<AprilTagFamilyHandle> family_;
  std::unique_ptr<apriltag_detector, DetectorDeleter> detector_;
};

}  // namespace calibench
