#include "detect/frame_detector.h"

#include <algorithm>
#include <map>

#include "core/tag_family.h"

namespace calibench {

bool FrameDetectorOptions::Check(std::string* why) const {
  if (!(min_border_distance_px >= 0)) {
    if (why) *why = "min_border_distance_px must be >= 0";
    return false;
  }
  return detector.Check(why) && refine.Check(why);
}

std::unique_ptr<FrameDetector> FrameDetector::Create(const std::vector<AprilGrid>& grids,
                                                     const FrameDetectorOptions& options,
                                                     std::string* why) {
  if (!options.Check(why)) return nullptr;
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return nullptr;
  };
  if (grids.empty()) return fail("the target has no AprilGrid");
  std::unique_ptr<FrameDetector> d(new FrameDetector());
  d->options_ = options;
  d->options_.detector.family = grids[0].family;
  for (size_t g = 0; g < grids.size(); ++g) {
    if (!grids[g].Check(why)) return nullptr;
    if (grids[g].family != grids[0].family) {
      return fail("grid " + std::to_string(g) + " uses " + grids[g].family + ", grid 0 uses " +
                  grids[0].family + ": one detector decodes one family");
    }
    const GridIds ids{grids[g].first_id, grids[g].NumTags(), d->num_points_};
    for (const GridIds& other : d->grids_) {
      if (ids.first_id < other.first_id + other.num_tags &&
          other.first_id < ids.first_id + ids.num_tags) {
        return fail("grid " + std::to_string(g) + " shares tag ids with an earlier grid");
      }
    }
    d->grids_.push_back(ids);
    d->num_points_ += 4 * ids.num_tags;
  }
  const auto family = TagFamily::Create(grids[0].family, why);
  if (!family) return nullptr;
  d->options_.refine.width_at_border = family->width_at_border();
  d->detector_ = AprilTagDetector::Create(d->options_.detector, why);
  if (!d->detector_) return nullptr;
  return d;
}

int FrameDetector::PointId(int id, int corner) const {
  for (const GridIds& g : grids_) {
    if (id >= g.first_id && id < g.first_id + g.num_tags) {
      return g.first_point + 4 * (id - g.first_id) + corner;
    }
  }
  return -1;
}

std::vector<Observation> FrameDetector::Detect(const GrayImage& image,
                                               DetectionCounts* counts) const {
  return Detect(image.pixels.data(), image.width, image.height, image.width, counts);
}

std::vector<Observation> FrameDetector::Detect(const uint8_t* pixels, int width, int height,
                                               int stride, DetectionCounts* counts) const {
  DetectionCounts local;
  std::vector<Observation> observations;
  const GrayImageView view(pixels, width, height, stride);
  std::vector<TagDetection> tags = detector_->Detect(pixels, width, height, stride);
  std::map<int, int> times_seen;
  for (const TagDetection& tag : tags) ++times_seen[tag.id];
  for (TagDetection& tag : tags) {
    if (PointId(tag.id, 0) < 0) {
      ++local.unknown_tags;
      continue;
    }
    if (times_seen[tag.id] > 1) {  // Which of them is the grid's tag is unknown: drop them all.
      ++local.duplicate_tags;
      continue;
    }
    bool near_border = false;
    for (const Eigen::Vector2d& c : tag.corners) {
      // Pixel centres at integers: the image spans [-0.5, width - 0.5] x [-0.5, height - 0.5].
      const double margin =
          std::min({c.x() + 0.5, c.y() + 0.5, width - 0.5 - c.x(), height - 0.5 - c.y()});
      near_border |= margin < options_.min_border_distance_px;
    }
    if (near_border) {
      ++local.border_tags;
      continue;
    }
    ++local.tags;
    if (options_.refine_corners && !RefineTagCorners(view, options_.refine, &tag)) {
      ++local.unrefined_tags;
    }
    for (int k = 0; k < 4; ++k) observations.push_back({PointId(tag.id, k), tag.corners[k]});
  }
  std::sort(observations.begin(), observations.end(),
            [](const Observation& a, const Observation& b) { return a.point_id < b.point_id; });
  if (counts) *counts = local;
  return observations;
}

}  // namespace calibench
