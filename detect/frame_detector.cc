#include "detect/frame_detector.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

#include "core/tag_family.h"

namespace calibench {
namespace {

// 3 x 3 maximum (gray dilation of white = erosion of black by one pixel), edges clamped.
std::vector<uint8_t> MaxFilter3x3(const GrayImageView& image) {
  const int w = image.width, h = image.height;
  std::vector<uint8_t> rows(static_cast<size_t>(w) * h), out(rows.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      rows[static_cast<size_t>(y) * w + x] = std::max(
          {image.at(std::max(x - 1, 0), y), image.at(x, y), image.at(std::min(x + 1, w - 1), y)});
    }
  }
  for (int y = 0; y < h; ++y) {
    const uint8_t* up = rows.data() + static_cast<size_t>(std::max(y - 1, 0)) * w;
    const uint8_t* mid = rows.data() + static_cast<size_t>(y) * w;
    const uint8_t* down = rows.data() + static_cast<size_t>(std::min(y + 1, h - 1)) * w;
    for (int x = 0; x < w; ++x)
      out[static_cast<size_t>(y) * w + x] = std::max({up[x], mid[x], down[x]});
  }
  return out;
}

// Moves each edge line of a tag found in the eroded image out by the erosion's shift |n_x| + |n_y|
// and re-intersects adjacent lines. False (tag unchanged) for a degenerate quad.
bool UndoErosion(TagDetection* tag) {
  const std::array<Eigen::Vector2d, 4>& p = tag->corners;
  const Eigen::Vector2d centre = 0.25 * (p[0] + p[1] + p[2] + p[3]);
  Eigen::Vector2d point[4], dir[4];
  for (int e = 0; e < 4; ++e) {
    const Eigen::Vector2d a = p[e], b = p[(e + 1) % 4];
    if ((b - a).norm() < 1e-9) return false;
    dir[e] = (b - a).normalized();
    Eigen::Vector2d n(dir[e].y(), -dir[e].x());
    if (n.dot(a - centre) < 0) n = -n;  // Outward.
    point[e] = a + (std::abs(n.x()) + std::abs(n.y())) * n;
  }
  std::array<Eigen::Vector2d, 4> moved;
  for (int k = 0; k < 4; ++k) {
    const int e0 = (k + 3) % 4, e1 = k;  // Corner k joins edges k - 1 and k.
    Eigen::Matrix2d m;
    m << dir[e0], -dir[e1];
    if (std::abs(m.determinant()) < 1e-9) return false;
    const Eigen::Vector2d t = m.inverse() * (point[e1] - point[e0]);
    moved[k] = point[e0] + t.x() * dir[e0];
  }
  tag->corners = moved;
  return true;
}

// The saddle point of each corner's X-junction (cv::cornerSubPix) in a window scaled to the
// corner squares (frame_detector.h); a corner that moves 1 px or more keeps its edge-fit value.
void RefineXJunctions(const GrayImageView& image, double square_fraction, TagDetection* tag) {
  constexpr int kMaxHalfWindowPx = 3;
  constexpr double kWindowOfSquare = 0.4, kMaxMovePx = 1.0;
  double edge_px = 0;
  for (int k = 0; k < 4; ++k)
    edge_px += 0.25 * (tag->corners[(k + 1) % 4] - tag->corners[k]).norm();
  const int half =
      std::min(kMaxHalfWindowPx, static_cast<int>(kWindowOfSquare * square_fraction * edge_px));
  if (half < 2) return;  // Squares of < 5 px: the window would reach other edges.
  const cv::Mat mat(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data),
                    static_cast<size_t>(image.stride));
  std::vector<cv::Point2f> points;
  for (const Eigen::Vector2d& c : tag->corners) {
    if (c.x() < half + 1 || c.y() < half + 1 || c.x() > image.width - half - 2 ||
        c.y() > image.height - half - 2) {
      return;  // The window would leave the image.
    }
    points.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
  }
  cv::cornerSubPix(mat, points, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::MAX_ITER, 30, 0.01));
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d refined(points[k].x, points[k].y);
    if ((refined - tag->corners[k]).norm() < kMaxMovePx) tag->corners[k] = refined;
  }
}

}  // namespace

namespace {
constexpr std::array<const char*, 3> kRefinementNames = {"none", "edge_fit", "photometric"};
}  // namespace

bool ParseCornerRefinement(const std::string& name, CornerRefinement* refinement) {
  for (size_t i = 0; i < kRefinementNames.size(); ++i) {
    if (name == kRefinementNames[i]) {
      *refinement = static_cast<CornerRefinement>(i);
      return true;
    }
  }
  return false;
}

const char* CornerRefinementName(CornerRefinement refinement) {
  const auto i = static_cast<size_t>(refinement);
  return i < kRefinementNames.size() ? kRefinementNames[i] : "unknown";
}

bool FrameDetectorOptions::Check(std::string* why) const {
  if (!(min_border_distance_px >= 0)) {
    if (why) *why = "min_border_distance_px must be >= 0";
    return false;
  }
  if (!(corner_square_fraction > 0 && corner_square_fraction <= 1)) {
    if (why) *why = "corner_square_fraction must lie in (0, 1]";
    return false;
  }
  if (camera && !camera->Check(why)) return false;
  return detector.Check(why) && refine.Check(why) && photometric.Check(why);
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
  d->options_.detector.black_border_bits = grids[0].black_tag_border;
  for (size_t g = 0; g < grids.size(); ++g) {
    if (!grids[g].Check(why)) return nullptr;
    if (grids[g].family != grids[0].family) {
      return fail("grid " + std::to_string(g) + " uses " + grids[g].family + ", grid 0 uses " +
                  grids[0].family + ": one detector decodes one family");
    }
    if (grids[g].black_tag_border != grids[0].black_tag_border) {
      return fail("grid " + std::to_string(g) + " has a " +
                  std::to_string(grids[g].black_tag_border) + "-bit black border, grid 0 a " +
                  std::to_string(grids[0].black_tag_border) +
                  "-bit one: one detector decodes one border width");
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
  d->family_ = TagFamily::Create(grids[0].family, grids[0].black_tag_border, why);
  if (!d->family_) return nullptr;
  d->options_.refine.width_at_border = d->family_->width_at_border();
  // Every tag's pattern for the photometric fit, once: tag index = point id / 4. The white
  // between tags is tag_spacing of the black square's side, at least the family's own white ring.
  // An id the family lacks keeps an empty pattern (its fit is refused).
  for (const AprilGrid& grid : grids) {
    const double margin = std::max(grid.tag_spacing * d->family_->width_at_border(),
                                   static_cast<double>(d->family_->border_start()));
    for (int t = 0; t < grid.NumTags(); ++t) {
      TagPattern pattern;
      if (!TagPattern::FromFamily(*d->family_, grid.first_id + t, margin, 0.0, &pattern, nullptr))
        pattern.black.clear();
      d->patterns_.push_back(std::move(pattern));
    }
  }
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
  if (options_.corner_squares) {
    std::map<int, int> found;
    for (const TagDetection& tag : tags) ++found[tag.id];
    const std::vector<uint8_t> eroded = MaxFilter3x3(view);
    for (TagDetection& tag : detector_->Detect(eroded.data(), width, height, width)) {
      if (found.count(tag.id) == 0 && UndoErosion(&tag)) tags.push_back(tag);
    }
  }
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
    std::array<double, 4> crlb_px;
    crlb_px.fill(std::numeric_limits<double>::quiet_NaN());
    const bool photometric =
        options_.refinement == CornerRefinement::kPhotometric && !options_.corner_squares;
    const bool edge_fit =
        options_.refinement == CornerRefinement::kEdgeFit ||
        (options_.refinement == CornerRefinement::kPhotometric && options_.corner_squares);
    if (photometric) {
      const PhotometricFitResult fit =
          FitTagPhotometric(view, patterns_[PointId(tag.id, 0) / 4], tag.corners,
                            options_.photometric, options_.camera ? &*options_.camera : nullptr);
      if (!fit.ok()) {
        ++local.refused_tags[static_cast<int>(fit.failure)];
        continue;
      }
      tag.corners = fit.corners;
      crlb_px = fit.crlb_px;
    }
    ++local.tags;
    if (edge_fit && !RefineTagCorners(view, options_.refine, &tag)) ++local.unrefined_tags;
    if (edge_fit && options_.corner_squares) {
      RefineXJunctions(view, options_.corner_square_fraction, &tag);
    }
    for (int k = 0; k < 4; ++k)
      observations.push_back({PointId(tag.id, k), tag.corners[k], crlb_px[k]});
  }
  std::sort(observations.begin(), observations.end(),
            [](const Observation& a, const Observation& b) { return a.point_id < b.point_id; });
  if (counts) *counts = local;
  return observations;
}

}  // namespace calibench
