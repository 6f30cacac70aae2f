// Kalibr's corner squares (frame_detector.h, "Grids with corner squares"): finding the tags they
// hide (an eroded copy, then the squares next to found tags painted out) and the saddle
// refinement of their X-junctions.
#include "detect/corner_squares.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "detect/frame_detector.h"
#include "detect/plane_to_image.h"

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

// Maps a tag's coordinates (its black square is [0, 1]^2) to pixels through the map of its
// detected corners (PlaneToImage: a homography, or with a distorted `camera` the tangent plane
// about the tag's centre ray projected by the lens), kept for consecutive squares of one tag.
class TagToPixel {
 public:
  explicit TagToPixel(const CameraIntrinsics* camera) : camera_(camera) {}
  // Prepares the map of `tag`; false when its corners leave the lens's valid region.
  bool SetTag(const TagDetection* tag) {
    if (tag == tag_) return mapped_;
    tag_ = tag;
    static const std::vector<Eigen::Vector2d> kUnit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mapped_ = to_image_.Fit(camera_, kUnit, {tag->corners.begin(), tag->corners.end()});
    return mapped_;
  }
  // False off the lens's valid region.
  bool operator()(const cv::Point2f& in_tag, cv::Point2f* pixel) const {
    Eigen::Vector2d p;
    if (!to_image_(Eigen::Vector2d(in_tag.x, in_tag.y), &p)) return false;
    *pixel = cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y()));
    return true;
  }

 private:
  const CameraIntrinsics* camera_;
  const TagDetection* tag_ = nullptr;
  bool mapped_ = false;
  PlaneToImage to_image_;
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

}  // namespace

// corner_squares.h.
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

// frame_detector.h: the eroded copy, then the squares of the tags found painted out, until a
// pass finds no new tag. A tag first found in the eroded copy takes the corners of a painted pass
// that sees it (its outline is then free of squares, not re-inflated), and so does a tag of the
// image itself that a square bent (below); an id seen twice in one image stays a duplicate
// (dropped by Detect).
void FrameDetector::FindTagsAmongSquares(const GrayImageView& view, const SquareMapping& mapping,
                                         std::vector<TagDetection>* tags,
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
    const std::vector<uint8_t> painted =
        PaintCornerSquares(view, SquaresNear(*tags, mapping), mapping.lens);
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
std::vector<SquareToPaint> FrameDetector::SquaresNear(const std::vector<TagDetection>& tags,
                                                      const SquareMapping& mapping) const {
  // Through a fisheye's bent edges a homography in pixels extrapolates badly: its own squares
  // only. Through a known lens the board plane is mapped exactly, and squares up to two tags away
  // are painted (the detector's raw corners, pulled in by painted tips, make the mapping drift by
  // a fraction of a pixel a pitch; measured on the EuRoC-like Kalibr views of
  // calibrate_images_test: 846 -> 850 of 864 tags sharp, 839 -> 855 at 1 px blur).
  const int reach = mapping.lens ? 3 : mapping.curved_edges ? 1 : 2;  // Distance + 1.
  std::vector<SquareToPaint> squares;
  for (const GridIds& g : grids_) {
    std::map<int, const TagDetection*> found;  // Tag index on the grid -> detection.
    for (const TagDetection& tag : tags) {
      if (tag.id >= g.first_id && tag.id < g.first_id + g.num_tags)
        found[tag.id - g.first_id] = &tag;
    }
    if (found.empty() || g.tag_cols < 1) continue;  // (tag_cols >= 1 when a tag was found.)
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

}  // namespace calibench
