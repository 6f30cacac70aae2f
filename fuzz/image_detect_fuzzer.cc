// libFuzzer target: image bytes -> 8-bit gray image -> FrameDetector (AprilTag 3 + corner
// refinement + matching to a 6 x 6 tag36h11 AprilGrid), the path of `calibench calibrate --images`
// and of the rendered source.
//
// Input formats:
//   - an encoded image (PNG, JPEG, BMP, TIFF, PGM: recognised by OpenCV's magic bytes), decoded
//     by cv::imdecode as `calibrate --images` reads files (grayscale);
//   - anything else is raw: byte 0 = width - 8, byte 1 = height - 8, then row-major pixels
//     (missing ones are 0), so the fuzzer can reach the detector without learning a codec.
// Decoded images above kMaxPixels are skipped (OpenCV's own limit is 2^30; the fuzzer's memory
// limit is the point of the cap, not a limit of the detector).
//
// Contract checked: no crash, hang or leak; every observation has a valid point id (0 <= id <
// NumPoints, ascending, unique) and a finite pixel inside the image (calibench convention: pixel
// centres at integers, so inside means [-0.5, size - 0.5]); counts are non-negative.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "detect/frame_detector.h"
#include "fuzz/fuzz_check.h"

namespace {

void Check(bool ok, const char* what, const std::string& context = "") {
  calibench::FuzzRequire(ok, "image_detect_fuzzer", what, context);
}

constexpr long kMaxPixels = 1L << 20;

const calibench::FrameDetector& Detector() {
  static const std::unique_ptr<calibench::FrameDetector> detector = [] {
    std::string why;
    auto d = calibench::FrameDetector::Create({calibench::AprilGrid()},
                                              calibench::FrameDetectorOptions(), &why);
    if (!d) {
      std::fprintf(stderr, "image_detect_fuzzer: %s\n", why.c_str());
      __builtin_trap();
    }
    return d;
  }();
  return *detector;
}

bool LooksEncoded(const uint8_t* data, size_t size) {
  if (size < 4) return false;
  const bool png = data[0] == 0x89 && data[1] == 'P' && data[2] == 'N' && data[3] == 'G';
  const bool jpeg = data[0] == 0xFF && data[1] == 0xD8;
  const bool bmp = data[0] == 'B' && data[1] == 'M';
  const bool tiff = (data[0] == 'I' && data[1] == 'I') || (data[0] == 'M' && data[1] == 'M');
  const bool pnm = data[0] == 'P' && data[1] >= '1' && data[1] <= '6';
  return png || jpeg || bmp || tiff || pnm;
}

cv::Mat ToGray(const uint8_t* data, size_t size) {
  if (LooksEncoded(data, size)) {
    const std::vector<uint8_t> bytes(data, data + size);
    return cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
  }
  if (size < 2) return cv::Mat();
  cv::Mat gray(data[1] + 8, data[0] + 8, CV_8UC1, cv::Scalar(0));
  const size_t n = std::min(size - 2, gray.total());
  std::copy(data + 2, data + 2 + n, gray.data);
  return gray;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const calibench::FrameDetector& detector = Detector();
  cv::Mat gray;
  try {
    gray = ToGray(data, size);
  } catch (const cv::Exception&) {  // A codec's refusal: `calibrate --images` skips the file.
    return 0;
  }
  if (gray.empty() || gray.type() != CV_8UC1 || static_cast<long>(gray.total()) > kMaxPixels) {
    return 0;
  }
  calibench::DetectionCounts counts;
  const std::vector<calibench::Observation> obs =
      detector.Detect(gray.data, gray.cols, gray.rows, static_cast<int>(gray.step), &counts);
  Check(counts.tags >= 0 && counts.unknown_tags >= 0 && counts.unrefined_tags >= 0 &&
            counts.border_tags >= 0,
        "negative count");
  Check(static_cast<long>(obs.size()) == 4L * counts.tags, "observations != 4 x tags");
  int previous = -1;
  for (const calibench::Observation& o : obs) {
    Check(o.point_id > previous && o.point_id < detector.NumPoints(), "bad point id order");
    previous = o.point_id;
    Check(o.pixel.allFinite(), "non-finite corner");
    Check(o.pixel.x() >= -0.5 && o.pixel.y() >= -0.5 && o.pixel.x() <= gray.cols - 0.5 &&
              o.pixel.y() <= gray.rows - 0.5,
          "corner outside the image");
  }
  return 0;
}
