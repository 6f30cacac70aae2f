#include "detect/frame_detector.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "detect/tangent_plane.h"
#include "sim/tag_family.h"

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

}  // namespace

// A corner square to paint out: its outline in the coordinates of the tag it is mapped through
// (the tag's black square is [0, 1]^2) and that tag's detected corners.
struct SquareToPaint {
  std::array<cv::Point2f, 4> in_tag;
  const TagDetection* tag;
};

namespace {

// Maps a tag's coordinates (its black square is [0, 1]^2) to pixels: through the homography of
// its detected corners, or with a distorted `camera` through the homography on the tangent plane
// about the tag's centre ray, projected by the lens (the ray e1 x + e2 y + c w keeps its direction
// for board points past the plane's horizon).
class TagToPixel {
 public:
  explicit TagToPixel(const CameraIntrinsics* camera) : camera_(camera) {}
  // Prepares the map of `tag`; false when its corners leave the lens's valid region.
  bool SetTag(const TagDetection* tag) {
    if (tag == tag_) return to_image_.has_value();
    tag_ = tag;
    to_image_.reset();
    std::vector<cv::Point2f> seen;
    if (!camera_) {
      for (const Eigen::Vector2d& c : tag->corners)
        seen.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
    } else {
      std::array<Eigen::Vector2d, 4> on_plane;
      if (TangentPlane::AboutPixels(*camera_, tag->corners, &plane_, &on_plane)) {
        for (const Eigen::Vector2d& q : on_plane)
          seen.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
      }
    }
    if (seen.size() != 4) return false;
    static const std::vector<cv::Point2f> kUnit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    Eigen::Matrix3d h;
    cv::cv2eigen(cv::getPerspectiveTransform(kUnit, seen), h);
    // h_22 = 1: w = 1 at the tag's corner 0, so w > 0 over the tag (it does not cross the
    // plane's horizon).
    to_image_ = h;
    return true;
  }
  // False off the lens's valid region.
  bool operator()(const cv::Point2f& in_tag, cv::Point2f* pixel) const {
    const Eigen::Vector3d mapped = *to_image_ * Eigen::Vector3d(in_tag.x, in_tag.y, 1);
    Eigen::Vector2d q;
    if (!camera_) {
      q = mapped.hnormalized();
    } else if (!ProjectPoint(*camera_, plane_.ToRayHomogeneous(mapped), &q)) {
      return false;
    }
    *pixel = cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y()));
    return true;
  }

 private:
  const CameraIntrinsics* camera_;
  const TagDetection* tag_ = nullptr;
  std::optional<Eigen::Matrix3d> to_image_;  // Unset: the tag's corners have no map.
  TangentPlane plane_;
};

// Fills the square's outline (grown by margin_px about its centre) with the brightest pixel of
// its neighbourhood in `original`. `outline`: per_side points a side, from corner 0. Nothing for a
// degenerate square or one off to infinity.
void PaintSquare(const std::vector<cv::Point2f>& outline, int per_side, double margin_px,
                 const cv::Mat& original, cv::Mat* painted) {
  auto corner = [&](int e) { return outline[(e % 4) * per_side]; };
  cv::Point2f centre(0, 0);
  for (int e = 0; e < 4; ++e) centre += 0.25f * corner(e);
  double inradius = std::numeric_limits<double>::infinity();
  for (int e = 0; e < 4; ++e) {
    const cv::Point2f d = corner(e + 1) - corner(e);
    const cv::Point2f r = centre - corner(e);
    const double len = std::hypot(d.x, d.y);
    if (len > 0) inradius = std::min(inradius, std::abs(d.x * r.y - d.y * r.x) / len);
  }
  if (!(inradius > 0.25) || !std::isfinite(inradius)) return;
  const float grow = static_cast<float>(1.0 + margin_px / inradius);
  constexpr int kShift = 4, kOne = 1 << kShift;  // fillConvexPoly's fractional bits.
  std::vector<cv::Point> polygon;
  for (const cv::Point2f& p : outline) {
    const cv::Point2f g = centre + grow * (p - centre);
    polygon.emplace_back(cvRound(g.x * kOne), cvRound(g.y * kOne));
  }
  const cv::Rect box = cv::boundingRect(polygon);
  const cv::Rect around =
      cv::Rect(box.x / kOne - 3, box.y / kOne - 3, box.width / kOne + 8, box.height / kOne + 8) &
      cv::Rect(0, 0, original.cols, original.rows);
  if (around.area() == 0) return;
  double white = 0;
  cv::minMaxLoc(original(around), nullptr, &white);
  // With a lens the sampled sides may bow inward by a fraction of a pixel: the convex fill
  // covers that sliver too, inside the margin.
  cv::fillConvexPoly(*painted, polygon, cv::Scalar(white), cv::LINE_8, kShift);
}

// A copy of `image` with every square of `squares` painted white, grown by kPaintMarginPx about
// its centre: with the squares gone, the tags that touch them stand alone, as on a grid without
// squares, and AprilTag 3 traces their outlines. Each square's white is the brightest pixel of its
// neighbourhood. Corners of painted tags lose a margin-sized tip, which changes nothing: the
// refinement runs on the original image. With a distorted `camera` each square is mapped
// through the lens (TagToPixel, its sides sampled and projected), so that squares a pitch away
// land where the lens puts them, past 90 deg from the axis too.
std::vector<uint8_t> PaintCornerSquares(const GrayImageView& image,
                                        const std::vector<SquareToPaint>& squares,
                                        const CameraIntrinsics* camera) {
  constexpr double kPaintMarginPx = 1.5;
  std::vector<uint8_t> copy(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y) {
    const uint8_t* row = image.data + static_cast<size_t>(y) * image.stride;
    std::copy(row, row + image.width, copy.data() + static_cast<size_t>(y) * image.width);
  }
  cv::Mat painted(image.height, image.width, CV_8UC1, copy.data());
  const cv::Mat original(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data),
                         static_cast<size_t>(image.stride));
  TagToPixel to_pixel(camera);
  // The square's outline: its corners, and with a lens 4 points a side (its sides bend).
  const int per_side = camera ? 4 : 1;
  for (const SquareToPaint& square : squares) {
    if (!to_pixel.SetTag(square.tag)) continue;
    std::vector<cv::Point2f> outline;
    bool mapped = true;
    for (int e = 0; e < 4 && mapped; ++e) {
      const cv::Point2f& from = square.in_tag[e];
      const cv::Point2f& to = square.in_tag[(e + 1) % 4];
      for (int k = 0; k < per_side && mapped; ++k) {
        cv::Point2f pixel;
        mapped = to_pixel(from + (to - from) * (static_cast<float>(k) / per_side), &pixel);
        outline.push_back(pixel);
      }
    }
    if (mapped) PaintSquare(outline, per_side, kPaintMarginPx, original, &painted);
  }
  return copy;
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
  if (!(max_predicted_residual_ratio >= 1)) {
    if (why) *why = "max_predicted_residual_ratio must be >= 1";
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
    if (grids[g].corner_squares != grids[0].corner_squares) {
      return fail("grid " + std::to_string(g) + (grids[g].corner_squares ? " has" : " has no") +
                  " corner squares, grid 0" + (grids[0].corner_squares ? " has" : " has none") +
                  ": one detector finds one layout");
    }
    if (grids[g].black_tag_border != grids[0].black_tag_border) {
      return fail("grid " + std::to_string(g) + " has a " +
                  std::to_string(grids[g].black_tag_border) + "-bit black border, grid 0 a " +
                  std::to_string(grids[0].black_tag_border) +
                  "-bit one: one detector decodes one border width");
    }
    const GridIds ids{grids[g].first_id, grids[g].NumTags(), d->num_points_,
                      grids[g].tag_rows, grids[g].tag_cols,  grids[g].tag_spacing};
    for (const GridIds& other : d->grids_) {
      if (ids.first_id < other.first_id + other.num_tags &&
          other.first_id < ids.first_id + ids.num_tags) {
        return fail("grid " + std::to_string(g) + " shares tag ids with an earlier grid");
      }
    }
    d->grids_.push_back(ids);
    d->num_points_ += 4 * ids.num_tags;
  }
  d->corner_squares_ = grids[0].corner_squares;
  d->family_ = TagFamily::Create(grids[0].family, grids[0].black_tag_border, why);
  if (!d->family_) return nullptr;
  d->options_.refine.width_at_border = d->family_->width_at_border();
  // Every tag's pattern for the photometric fit, once: tag index = point id / 4. The white
  // between tags is tag_spacing of the black square's side, at least the family's own white ring;
  // the corner squares fill it at the corners. An id the family lacks keeps an empty pattern (its
  // fit is refused).
  for (const AprilGrid& grid : grids) {
    const double gap_cells = grid.tag_spacing * d->family_->width_at_border();
    const double margin = std::max(gap_cells, static_cast<double>(d->family_->border_start()));
    const double squares = grid.corner_squares ? gap_cells : 0.0;
    for (int t = 0; t < grid.NumTags(); ++t) {
      TagPattern pattern;
      if (!TagPattern::FromFamily(*d->family_, grid.first_id + t, margin, squares, &pattern,
                                  nullptr))
        pattern.black.clear();
      d->patterns_.push_back(std::move(pattern));
    }
  }
  d->detector_ = AprilTagDetector::Create(d->options_.detector, why);
  if (!d->detector_) return nullptr;
  return d;
}

// frame_detector.h: the eroded copy, then the squares of the tags found painted out, until a
// pass finds no new tag. A tag first found in the eroded copy takes the corners of a painted pass
// that sees it (its outline is then free of squares, not re-inflated), and so does a tag of the
// image itself that a square bent (below); an id seen twice in one image stays a duplicate
// (dropped by Detect).
void FrameDetector::FindTagsAmongSquares(const GrayImageView& view, std::vector<TagDetection>* tags,
                                         std::vector<bool>* from_copy) const {
  constexpr int kMaxPaintPasses = 3;
  // A tag of the image itself whose painted-pass corners are farther than this from its own was
  // joined to a square there (its outline bent round it: measured up to 7 px off): it takes the
  // painted pass's corners (off by the painted tips only, < 1 px).
  constexpr double kDisagreePx = 1.0;
  std::map<int, int> times_in_first;
  for (const TagDetection& tag : *tags) ++times_in_first[tag.id];
  std::map<int, int> found;       // Id -> index in *tags, or -1 for a duplicate.
  std::vector<bool> replaceable;  // Per tag: its corners came from the eroded copy.
  for (size_t i = 0; i < tags->size(); ++i) {
    found[(*tags)[i].id] = times_in_first[(*tags)[i].id] > 1 ? -1 : static_cast<int>(i);
    replaceable.push_back(false);
  }
  auto add = [&](const TagDetection& tag, bool eroded) {
    const auto it = found.find(tag.id);
    if (it == found.end()) {
      found[tag.id] = static_cast<int>(tags->size());
      tags->push_back(tag);
      from_copy->push_back(true);
      replaceable.push_back(eroded);
      return true;
    }
    if (eroded || it->second < 0) return false;
    TagDetection& known = (*tags)[it->second];
    double moved_px = 0;
    for (int k = 0; k < 4; ++k)
      moved_px = std::max(moved_px, (tag.corners[k] - known.corners[k]).norm());
    if (replaceable[it->second] || moved_px > kDisagreePx) {
      known.corners = tag.corners;
      (*from_copy)[it->second] = true;
      replaceable[it->second] = false;
    }
    return false;
  };
  const std::vector<uint8_t> eroded = MaxFilter3x3(view);
  for (TagDetection& tag : detector_->Detect(eroded.data(), view.width, view.height, view.width)) {
    if (found.count(tag.id) == 0 && UndoErosion(&tag)) add(tag, true);
  }
  for (int pass = 0; pass < kMaxPaintPasses && !tags->empty(); ++pass) {
    const std::vector<uint8_t> painted = PaintCornerSquares(view, SquaresNear(*tags), SquareLens());
    const std::vector<TagDetection> seen =
        detector_->Detect(painted.data(), view.width, view.height, view.width);
    std::map<int, int> times_in_pass;
    for (const TagDetection& tag : seen) ++times_in_pass[tag.id];
    int added = 0;
    for (const TagDetection& tag : seen) {
      if (times_in_pass[tag.id] == 1 && add(tag, false)) ++added;
    }
    if (added == 0) break;
  }
}

// Square (i, j) spans [i p - g, i p] x [j p - g, j p] on the board (sim/target.h), i.e.
// [(i - c)(1 + q) - q, (i - c)(1 + q)] x (the same in j, r) in the coordinates of tag (r, c) (its
// black square [0, 1]^2, q = g / s = tag_spacing). Each square within one tag of a found tag (two
// through a known lens; Chebyshev distance in tags: 0 for the tag's own four) is mapped through
// the nearest such tag: exact for its own squares, extrapolated for the next rings.
std::vector<SquareToPaint> FrameDetector::SquaresNear(const std::vector<TagDetection>& tags) const {
  // Through a fisheye's bent edges a homography in pixels extrapolates badly: its own squares
  // only. Through a known lens the board plane is mapped exactly, and squares up to two tags away
  // are painted (the detector's raw corners, pulled in by painted tips, make the mapping drift by
  // a fraction of a pixel a pitch; measured on the EuRoC-like Kalibr views of
  // calibrate_images_test: 846 -> 850 of 864 tags sharp, 839 -> 855 at 1 px blur).
  const int reach = SquareLens() ? 3 : options_.refine.curved_edges ? 1 : 2;  // Distance + 1.
  std::vector<SquareToPaint> squares;
  for (const GridIds& g : grids_) {
    std::map<int, const TagDetection*> found;  // Tag index on the grid -> detection.
    for (const TagDetection& tag : tags) {
      if (tag.id >= g.first_id && tag.id < g.first_id + g.num_tags)
        found[tag.id - g.first_id] = &tag;
    }
    if (found.empty()) continue;
    auto distance = [](int i, int c) { return i < c ? c - i : std::max(0, i - c - 1); };
    for (int j = 0; j <= g.tag_rows; ++j) {
      for (int i = 0; i <= g.tag_cols; ++i) {
        int best = reach, r = 0, c = 0;
        const TagDetection* through = nullptr;
        for (const auto& [index, tag] : found) {
          const int tr = index / g.tag_cols, tc = index % g.tag_cols;
          const int d = std::max(distance(i, tc), distance(j, tr));
          if (d < best) best = d, r = tr, c = tc, through = tag;
        }
        if (!through) continue;
        const double q = g.tag_spacing;
        const auto x1 = static_cast<float>((i - c) * (1 + q)), x0 = static_cast<float>(x1 - q);
        const auto y1 = static_cast<float>((j - r) * (1 + q)), y0 = static_cast<float>(y1 - q);
        squares.push_back({{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}, through});
      }
    }
  }
  std::stable_sort(squares.begin(), squares.end(),
                   [](const SquareToPaint& a, const SquareToPaint& b) { return a.tag < b.tag; });
  return squares;
}

const CameraIntrinsics* FrameDetector::SquareLens() const {
  return options_.camera && options_.camera->IsDistorted() ? &*options_.camera : nullptr;
}

const FrameDetector::GridIds* FrameDetector::GridOf(int id) const {
  for (const GridIds& g : grids_) {
    if (id >= g.first_id && id < g.first_id + g.num_tags) return &g;
  }
  return nullptr;
}

int FrameDetector::PointId(int id, int corner) const {
  const GridIds* g = GridOf(id);
  return g ? g->first_point + 4 * (id - g->first_id) + corner : -1;
}

std::vector<Observation> FrameDetector::Detect(const GrayImage& image,
                                               DetectionCounts* counts) const {
  return Detect(image.pixels.data(), image.width, image.height, image.width, counts);
}

std::vector<Observation> FrameDetector::Detect(const uint8_t* pixels, int width, int height,
                                               int stride, DetectionCounts* counts) const {
  const GrayImageView view(pixels, width, height, stride);
  return RefineTags(view, FindTags(view), options_.camera ? &*options_.camera : nullptr, counts);
}

FoundTags FrameDetector::FindTags(const GrayImageView& view) const {
  FoundTags found;
  std::vector<TagDetection> tags =
      detector_->Detect(view.data, view.width, view.height, view.stride);
  std::vector<bool> from_copy(tags.size(), false);
  if (corner_squares_) FindTagsAmongSquares(view, &tags, &from_copy);
  std::map<int, int> times_seen;
  for (const TagDetection& tag : tags) ++times_seen[tag.id];
  for (size_t t = 0; t < tags.size(); ++t) {
    const TagDetection& tag = tags[t];
    if (PointId(tag.id, 0) < 0) {
      ++found.counts.unknown_tags;
      continue;
    }
    if (times_seen[tag.id] > 1) {  // Which of them is the grid's tag is unknown: drop them all.
      ++found.counts.duplicate_tags;
      continue;
    }
    if (NearBorder(tag.corners, view)) {
      ++found.counts.border_tags;
      continue;
    }
    found.tags.push_back(tag);
    found.from_copy.push_back(from_copy[t]);
  }
  return found;
}

bool FrameDetector::NearBorder(const std::array<Eigen::Vector2d, 4>& corners,
                               const GrayImageView& view) const {
  for (const Eigen::Vector2d& c : corners) {
    // Pixel centres at integers: the image spans [-0.5, width - 0.5] x [-0.5, height - 0.5].
    const double margin =
        std::min({c.x() + 0.5, c.y() + 0.5, view.width - 0.5 - c.x(), view.height - 0.5 - c.y()});
    if (!(margin >= options_.min_border_distance_px)) return true;
  }
  return false;
}

std::vector<Observation> FrameDetector::RefineTags(const GrayImageView& view,
                                                   const FoundTags& found,
                                                   const CameraIntrinsics* camera,
                                                   DetectionCounts* counts) const {
  DetectionCounts local = found.counts;
  std::vector<FittedTag> fitted;
  const bool photometric = options_.refinement == CornerRefinement::kPhotometric;
  const bool edge_fit = options_.refinement == CornerRefinement::kEdgeFit;
  for (size_t t = 0; t < found.tags.size(); ++t) {
    TagDetection tag = found.tags[t];
    FittedTag out{tag.id, {}, {}, std::numeric_limits<double>::quiet_NaN()};
    out.crlb_px.fill(std::numeric_limits<double>::quiet_NaN());
    if (photometric) {
      const PhotometricFitResult fit = FitTagPhotometric(view, patterns_[PointId(tag.id, 0) / 4],
                                                         tag.corners, options_.photometric, camera);
      if (!fit.ok()) {
        ++local.refused_tags[static_cast<int>(fit.failure)];
        continue;
      }
      tag.corners = fit.corners;
      out.crlb_px = fit.crlb_px;
      out.residual_rms_gray = fit.residual_rms_gray;
    }
    if (edge_fit && !RefineTagCorners(view, options_.refine, &tag)) {
      // Raw corners of a modified copy are biased: no refinement, no tag.
      if (found.from_copy[t]) {
        ++local.unrefined_copy_tags;
        continue;
      }
      ++local.unrefined_tags;
    }
    ++local.tags;
    if (edge_fit && corner_squares_) {
      RefineXJunctions(view, std::min(1.0, GridOf(tag.id)->tag_spacing), &tag);
    }
    out.corners = tag.corners;
    fitted.push_back(out);
  }
  if (photometric && options_.predict_missing_tags) {
    std::set<int> tried;
    for (const TagDetection& tag : found.tags) tried.insert(tag.id);
    PredictMissingTags(view, camera, std::move(tried), &fitted, &local);
  }
  std::vector<Observation> observations;
  for (const FittedTag& tag : fitted) {
    for (int k = 0; k < 4; ++k)
      observations.push_back({PointId(tag.id, k), tag.corners[k], tag.crlb_px[k]});
  }
  std::sort(observations.begin(), observations.end(),
            [](const Observation& a, const Observation& b) { return a.point_id < b.point_id; });
  if (counts) *counts = local;
  return observations;
}

void FrameDetector::PredictMissingTags(const GrayImageView& view, const CameraIntrinsics* camera,
                                       std::set<int> tried, std::vector<FittedTag>* fitted,
                                       DetectionCounts* counts) const {
  std::vector<double> residuals;
  for (const FittedTag& tag : *fitted) residuals.push_back(tag.residual_rms_gray);
  if (residuals.empty()) return;
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  const double max_residual_gray =
      options_.max_predicted_residual_ratio * residuals[residuals.size() / 2];
  const bool lens = camera && camera->IsDistorted();
  // Through a wide lens the tags AprilTag 3 misses are the squeezed ones at the image circle's
  // edge, where fitted corners were measured to carry a bias that moves a calibration's lens
  // parameters by 3-7 std (tests/bench/calibrate_wide_rendered_test.cc, 190 deg eucm and double
  // sphere): no tag is predicted farther off the axis than a fitted decoded tag's corner.
  auto off_axis = [&](const Eigen::Vector2d& pixel) {
    Eigen::Vector3d ray;
    return UnprojectToRay(*camera, pixel, &ray) ? std::acos(ray.normalized().z()) : M_PI;
  };
  double max_off_axis = 0;
  if (lens) {
    for (const FittedTag& tag : *fitted)
      for (const Eigen::Vector2d& c : tag.corners)
        max_off_axis = std::max(max_off_axis, off_axis(c));
  }
  // Chebyshev distance in tags: a homography in pixels through a fisheye's bent edges holds over
  // one tag only.
  const int reach = !lens && options_.refine.curved_edges ? 1 : 2;
  constexpr int kMaxPasses = 3;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    int added = 0;
    for (const GridIds& g : grids_) {
      for (int index = 0; index < g.num_tags; ++index) {
        const int id = g.first_id + index;
        if (tried.count(id) > 0) continue;
        const int r = index / g.tag_cols, c = index % g.tag_cols;
        std::vector<const FittedTag*> near;
        for (const FittedTag& tag : *fitted) {
          const int other = tag.id - g.first_id;
          if (other < 0 || other >= g.num_tags) continue;
          if (std::max(std::abs(other / g.tag_cols - r), std::abs(other % g.tag_cols - c)) <= reach)
            near.push_back(&tag);
        }
        std::array<Eigen::Vector2d, 4> corners;
        if (near.empty() || !PredictCorners(g, index, near, camera, &corners) ||
            NearBorder(corners, view)) {
          continue;
        }
        if (lens) {  // Not past the field the decoded tags reach.
          bool beyond = false;
          for (const Eigen::Vector2d& corner : corners) beyond |= off_axis(corner) > max_off_axis;
          if (beyond) continue;
        }
        tried.insert(id);
        const PhotometricFitResult fit = FitTagPhotometric(view, patterns_[PointId(id, 0) / 4],
                                                           corners, options_.photometric, camera);
        if (!fit.ok() || !(fit.residual_rms_gray <= max_residual_gray)) {
          ++counts->refused_predictions;
          continue;
        }
        fitted->push_back({id, fit.corners, fit.crlb_px, fit.residual_rms_gray});
        ++counts->tags;
        ++counts->predicted_tags;
        ++added;
      }
    }
    if (added == 0) break;
  }
}

bool FrameDetector::PredictCorners(const GridIds& g, int index,
                                   const std::vector<const FittedTag*>& near,
                                   const CameraIntrinsics* camera,
                                   std::array<Eigen::Vector2d, 4>* corners) const {
  // A fit of the neighbours' corners worse than this: the image is not a homography of the board
  // over this patch (an unknown lens), and the prediction would not be one either.
  constexpr double kMaxNeighbourResidualPx = 0.5;
  // Corner k of tag i on the board, in tag edges (sim/target.h: the black square of tag (r, c)
  // spans [c p, c p + 1] x [r p, r p + 1], corners bottom-left, bottom-right, top-right,
  // top-left).
  const double pitch = 1 + g.tag_spacing;
  auto on_board = [&](int i, int k) {
    static constexpr int kDx[4] = {0, 1, 1, 0}, kDy[4] = {0, 0, 1, 1};
    const int row = i / g.tag_cols, col = i % g.tag_cols;
    return cv::Point2d(col * pitch + kDx[k], row * pitch + kDy[k]);
  };
  const bool lens = camera && camera->IsDistorted();
  TangentPlane plane;
  if (lens) {
    Eigen::Vector3d mean_ray = Eigen::Vector3d::Zero();
    for (const FittedTag* tag : near) {
      for (const Eigen::Vector2d& pixel : tag->corners) {
        Eigen::Vector3d ray;
        if (!UnprojectToRay(*camera, pixel, &ray)) return false;
        mean_ray += ray.normalized();
      }
    }
    if (!TangentPlane::About(mean_ray, &plane)) return false;
  }
  std::vector<cv::Point2d> board, seen;
  for (const FittedTag* tag : near) {
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector2d q = tag->corners[k];
      if (lens && !plane.FromPixel(*camera, tag->corners[k], &q)) return false;
      board.push_back(on_board(tag->id - g.first_id, k));
      seen.emplace_back(q.x(), q.y());
    }
  }
  const cv::Mat h_cv = cv::findHomography(board, seen, 0);
  if (h_cv.empty()) return false;
  Eigen::Matrix3d seen_from_board;
  cv::cv2eigen(h_cv, seen_from_board);
  // The board's points in front share the sign of w with the neighbours' (a tangent plane point
  // past its horizon has w < 0, and its ray still has its direction).
  const double w_sign =
      (seen_from_board * Eigen::Vector3d(board[0].x, board[0].y, 1)).z() > 0 ? 1 : -1;
  auto to_pixel = [&](const cv::Point2d& b, Eigen::Vector2d* pixel) {
    const Eigen::Vector3d h = w_sign * (seen_from_board * Eigen::Vector3d(b.x, b.y, 1));
    if (lens) return ProjectPoint(*camera, plane.ToRayHomogeneous(h), pixel);
    if (!(h.z() > 0)) return false;
    *pixel = h.hnormalized();
    return true;
  };
  size_t n = 0;
  for (const FittedTag* tag : near) {
    for (int k = 0; k < 4; ++k, ++n) {
      Eigen::Vector2d pixel;
      if (!to_pixel(board[n], &pixel) ||
          !((pixel - tag->corners[k]).norm() <= kMaxNeighbourResidualPx))
        return false;
    }
  }
  for (int k = 0; k < 4; ++k) {
    if (!to_pixel(on_board(index, k), &(*corners)[k])) return false;
  }
  return true;
}

}  // namespace calibench
