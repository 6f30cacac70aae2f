#include "detect/apriltag_detector.h"

#include <apriltag/apriltag.h>

#include <algorithm>

#include "sim/tag_family.h"

namespace calibench {
namespace {

// AprilTag 3 puts pixel centres at (i + 0.5, j + 0.5); calibench at (i, j).
constexpr double kAprilTagToCalibenchPx = -0.5;

}  // namespace

bool AprilTagOptions::Check(std::string* why) const {
  std::string msg;
  std::string border_why;
  AprilTagFamilyFunctions f;
  if (!FindAprilTagFamily(family, &f)) {
    msg = "unknown AprilTag family '" + family + "'";
  } else if (!CheckBorderBits(family, black_border_bits, &border_why)) {
    msg = "black_border_bits: " + border_why;
  }
  if (!(quad_decimate >= 1)) msg = "quad_decimate must be >= 1";
  if (!(quad_sigma >= 0)) msg = "quad_sigma must be >= 0";
  if (threads < 1) msg = "threads must be >= 1";
  if (max_hamming < 0 || max_hamming > 3) msg = "max_hamming must lie in [0, 3]";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

void AprilTagDetector::DetectorDeleter::operator()(apriltag_detector* d) const {
  apriltag_detector_destroy(d);
}

AprilTagDetector::~AprilTagDetector() {
  detector_.reset();  // The detector refers to the family: release it first.
  family_.reset();
}

std::unique_ptr<AprilTagDetector> AprilTagDetector::Create(const AprilTagOptions& options,
                                                           std::string* why) {
  if (!options.Check(why)) return nullptr;
  std::unique_ptr<AprilTagDetector> d(new AprilTagDetector());
  d->family_ = AprilTagFamilyHandle::Create(options.family, options.black_border_bits, why);
  if (!d->family_) return nullptr;
  d->detector_.reset(apriltag_detector_create());
  if (!d->family_ || !d->detector_) {
    if (why) *why = "apriltag: cannot create the detector";
    return nullptr;
  }
  apriltag_detector_add_family_bits(d->detector_.get(), d->family_->get(), options.max_hamming);
  d->detector_->quad_decimate = static_cast<float>(options.quad_decimate);
  d->detector_->quad_sigma = static_cast<float>(options.quad_sigma);
  d->detector_->refine_edges = options.refine_edges;
  d->detector_->decode_sharpening = options.decode_sharpening;
  d->detector_->nthreads = options.threads;
  return d;
}

std::vector<TagDetection> AprilTagDetector::Detect(const GrayImage& image) const {
  return Detect(image.pixels.data(), image.width, image.height, image.width);
}

std::vector<TagDetection> AprilTagDetector::Detect(const uint8_t* pixels, int width, int height,
                                                   int stride) const {
  // A view, no copy: the detector only reads the buffer.
  image_u8_t view{width, height, stride, const_cast<uint8_t*>(pixels)};
  const std::unique_ptr<zarray_t, void (*)(zarray_t*)> detections(
      apriltag_detector_detect(detector_.get(), &view), apriltag_detections_destroy);
  std::vector<TagDetection> out;
  for (int i = 0; i < zarray_size(detections.get()); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(detections.get(), i, &det);
    TagDetection t;
    t.id = det->id;
    t.hamming = det->hamming;
    t.decision_margin = det->decision_margin;
    for (int k = 0; k < 4; ++k) {
      t.corners[k] = Eigen::Vector2d(det->p[k][0], det->p[k][1]).array() + kAprilTagToCalibenchPx;
    }
    out.push_back(t);
  }
  std::sort(out.begin(), out.end(),
            [](const TagDetection& a, const TagDetection& b) { return a.id < b.id; });
  return out;
}

}  // namespace calibench
