// The renderer's inner pieces (sim/render.h; render.cc's FrameRenderer uses them): one board of a
// frame as seen along rays (its ray -> board homography, the shade of a board point from the tag
// bitmaps and Kalibr's corner squares, the exact mean shade over a pixel's footprint on it, its
// pixel bounds), how the ray table holds a ray in two numbers, and the n x n sample pattern of a
// pixel. Internal to sim/: not part of its API.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "sim/render.h"

namespace calibench {
namespace render_internal {

constexpr int kOffBoard = -1;  // The hit of a ray that meets no board.

// floor() without a library call (x86-64 baseline has no SSE4.1 rounding); |x| < 2^31.
inline int FastFloor(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i);
}

// floor() of a cell or tag index, |x| < 2^15: one truncation of a positive number.
inline int FloorSmall(double x) {
  constexpr int kOffset = 1 << 15;
  return static_cast<int>(x + kOffset) - kOffset;
}

// How the ray table holds a ray in two numbers (render.h). kPlane: (x, y) = (X, Y) / Z on the plane
// z = 1, rays in front only (radtan); kStereographic: (x, y) = (X, Y) / (|P| + Z), every ray but
// the backward axis (the equidistant family, whose image reaches 90 deg from the axis, and the
// omnidirectional ones, whose rays reach past it). The plane's coordinates grow as tan(theta),
// too fast near 90 deg for the interpolation between pixel corners and a pixel's straight-sided
// footprint: through a 160 deg equidistant lens, noise-free corners within 6 px of its 90 deg
// edge came out +0.0018 px outwards on average (max error 0.0067 px); in stereographic
// coordinates, which grow as tan(theta / 2), -0.0002 px (max 0.0027;
// tests/detect/wide_angle_test.cc).
// Each family declares its space (LensFamilyInfo::ray_space, camera/lens_families.h).
using RaySpace = LensRaySpace;

inline RaySpace RaySpaceOf(LensFamily family) { return InfoOf(family).ray_space; }
inline bool IsPlaneFamily(LensFamily family) { return RaySpaceOf(family) == RaySpace::kPlane; }

// The pixel of `point_in_cam` for an image bound: false where it does not project (radtan and
// equidistant: z <= 0) or where the distortion folds over (d r_d / d r <= 0), so that a bound
// from projected outline points holds the whole shape between them.
inline bool ProjectUnfolded(const CameraIntrinsics& k, const Eigen::Vector3d& point_in_cam,
                            Eigen::Vector2d* pixel) {
  const Eigen::Vector3d& p = point_in_cam;
  if (IsPlaneFamily(k.family)) {
    if (!(p.z() > 1e-9)) return false;
    if (!k.DistortionIsMonotoneAt((p.x() * p.x() + p.y() * p.y()) / (p.z() * p.z()))) return false;
  } else if (!k.DistortionIsMonotoneAlong(p)) {
    return false;
  }
  return ProjectPoint(k, p, pixel) && pixel->allFinite();
}

// The homogeneous ray (a positive multiple of the unit ray) of table coordinates q: (x, y, 1), or
// the inverse stereographic projection (2x, 2y, 1 - x^2 - y^2) = (2 / (1 + Z)) P for a unit P.
inline Eigen::Vector3d LiftRay(RaySpace space, const Eigen::Vector2d& q) {
  if (space == RaySpace::kPlane) return {q.x(), q.y(), 1.0};
  return {2 * q.x(), 2 * q.y(), 1 - q.squaredNorm()};
}

// The stereographic coordinates of a unit ray; NaN at the backward axis.
inline Eigen::Vector2d Stereographic(const Eigen::Vector3d& unit_ray) {
  const double w = 1 + unit_ray.z();
  if (!(w > 1e-12)) return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return unit_ray.head<2>() / w;
}

// A convex polygon: a pixel's footprint on a board (4 vertices) clipped by up to four axis-parallel
// lines (at most one vertex more per line; room for rounding's extra crossings).
struct SmallPolygon {
  static constexpr int kCapacity = 16;
  std::array<Eigen::Vector2d, kCapacity> v;
  int n = 0;
};

// Sutherland-Hodgman: the part of `in` where coordinate `axis` is >= value (keep_above) or <=
// value.
inline void ClipToHalfPlane(const SmallPolygon& in, int axis, double value, bool keep_above,
                            SmallPolygon* out) {
  out->n = 0;
  if (in.n == 0) return;
  const double sign = keep_above ? 1.0 : -1.0;
  const Eigen::Vector2d* a = &in.v[in.n - 1];  // Each edge a -> b, the closing edge first.
  double da = sign * ((*a)[axis] - value);
  for (int k = 0; k < in.n; ++k) {
    const Eigen::Vector2d& b = in.v[k];
    const double db = sign * (b[axis] - value);
    if ((da >= 0) != (db >= 0) && out->n < SmallPolygon::kCapacity) {
      out->v[out->n++] = *a + (da / (da - db)) * (b - *a);
    }
    if (db >= 0 && out->n < SmallPolygon::kCapacity) out->v[out->n++] = b;
    a = &b;
    da = db;
  }
}

// The homography from a pixel's unit square (fa, fb) in [0, 1]^2 to its footprint on a board, the
// quadrilateral of its corners' board points q0 = b(0, 0), q1 = b(1, 0), q2 = b(1, 1), q3 = b(0, 1)
// (Heckbert 1989, square to quadrilateral), held as its inverse: the pixel coordinates of a board
// point. A pinhole camera's pixel -> board map is this homography exactly; through a lens (the rays
// inside a pixel interpolated between its corners') it holds to second order in the pixel's size,
// so pixel areas computed through it carry the first-order change of scale across the pixel (the
// board's perspective, the lens's compression) that board areas would miss.
class PixelFromBoard {
 public:
  // q in local coordinates with q0 = (0, 0). False for a degenerate quadrilateral.
  bool Init(const SmallPolygon& q) {
    const double x1 = q.v[1].x(), x2 = q.v[2].x(), x3 = q.v[3].x();
    const double y1 = q.v[1].y(), y2 = q.v[2].y(), y3 = q.v[3].y();
    const double sx = -x1 + x2 - x3, sy = -y1 + y2 - y3;
    const double dx1 = x1 - x2, dx2 = x3 - x2, dy1 = y1 - y2, dy2 = y3 - y2;
    const double den = dx1 * dy2 - dx2 * dy1;
    if (!(std::abs(den) > 0)) return false;
    const double g = (sx * dy2 - dx2 * sy) / den, h = (dx1 * sy - sx * dy1) / den;
    Eigen::Matrix3d board_from_pixel;
    board_from_pixel << x1 + g * x1, x3 + h * x3, 0, y1 + g * y1, y3 + h * y3, 0, g, h, 1;
    const double det = board_from_pixel.determinant();
    if (!(std::abs(det) > 0)) return false;
    pixel_from_board_ = board_from_pixel.inverse();
    return true;
  }

  // Twice the signed area, in pixels, of a polygon of the footprint (local board coordinates).
  double TwicePixelArea(const SmallPolygon& p) const {
    if (p.n == 0) return 0;
    const Eigen::Matrix3d& m = pixel_from_board_;
    const auto map = [&m](const Eigen::Vector2d& b) {
      const double w = 1.0 / (m(2, 0) * b.x() + m(2, 1) * b.y() + m(2, 2));
      return Eigen::Vector2d((m(0, 0) * b.x() + m(0, 1) * b.y() + m(0, 2)) * w,
                             (m(1, 0) * b.x() + m(1, 1) * b.y() + m(1, 2)) * w);
    };
    double sum = 0;
    Eigen::Vector2d a = map(p.v[p.n - 1]);
    for (int k = 0; k < p.n; ++k) {
      const Eigen::Vector2d b = map(p.v[k]);
      sum += a.x() * b.y() - a.y() * b.x();
      a = b;
    }
    return sum;
  }

 private:
  Eigen::Matrix3d pixel_from_board_;
};

// The lines coordinate = const of one axis that cross an interval, ascending; full when more than
// kMax cross it (cells far smaller than a pixel).
struct AxisLines {
  static constexpr int kMax = 12;
  std::array<double, kMax> at;
  int n = 0;
  bool full = false;
  void Add(double x, double lo, double hi) {
    if (!(x > lo && x < hi)) return;
    if (n == kMax) {
      full = true;
      return;
    }
    at[n++] = x;
  }
};

// One board of the frame: its ray -> board homography and a table of its cells' shades.
class BoardShader {
 public:
  // `ray_map` maps the renderer's table rays to the rays of the frame's camera (identity unless
  // the intrinsics changed: FrameRenderer::Render).
  bool Init(const BoardView& view, const Eigen::Matrix3d& ray_map, std::string* why) {
    const AprilGrid& g = view.grid;
    const TagFamily& f = *view.family;
    if (f.name() != g.family || f.border_bits() != g.black_tag_border) {
      if (why)
        *why = "board family '" + g.family + "' with a " + std::to_string(g.black_tag_border) +
               "-bit border has no matching TagFamily (given: " + f.name() + ", " +
               std::to_string(f.border_bits()) + "-bit border)";
      return false;
    }
    if (!g.Check(why)) return false;  // Ids past the family's codes, among others.
    Eigen::Matrix3d plane;            // [r1 r2 t]: board (bx, by, 1) -> camera ray.
    plane << view.cam_from_board.rotation.col(0), view.cam_from_board.rotation.col(1),
        view.cam_from_board.translation;
    visible_ = std::abs(plane.determinant()) > 1e-15;  // Not seen edge-on.
    if (visible_) board_from_ray_ = plane.inverse() * ray_map;
    cell_ = g.tag_size_m / f.width_at_border();
    inv_cell_ = 1.0 / cell_;
    pitch_ = g.Pitch();
    inv_pitch_ = 1.0 / pitch_;
    gap_ = pitch_ - g.tag_size_m;
    corner_squares_ = g.corner_squares;
    const double margin = (corner_squares_ ? 2 : 1) * gap_;  // White beyond the outer squares.
    min_ = -margin;
    max_x_ = g.tag_cols * pitch_ - (pitch_ - g.tag_size_m) + margin;
    max_y_ = g.tag_rows * pitch_ - (pitch_ - g.tag_size_m) + margin;
    start_ = f.border_start();
    width_ = f.total_width();
    cols_ = g.tag_cols;
    rows_ = g.tag_rows;
    const int max_tags_per_side = 0xFFFF / (width_ + 1) - 2;  // Cell keys fit 16 bits.
    if (std::max(cols_, rows_) > max_tags_per_side) {
      if (why)
        *why = "the renderer takes at most " + std::to_string(max_tags_per_side) + " " + g.family +
               " tags along a side of a grid (given " + std::to_string(std::max(cols_, rows_)) +
               ")";
      return false;
    }
    // Cell (X, Y) = (c * width + col, r * width + row_from_bottom), X fastest.
    cells_.resize(static_cast<size_t>(rows_) * width_ * cols_ * width_);
    for (int r = 0; r < rows_; ++r) {
      for (int c = 0; c < cols_; ++c) {
        for (int row = 0; row < width_; ++row) {
          for (int col = 0; col < width_; ++col) {
            cells_[(static_cast<size_t>(r) * width_ + row) * cols_ * width_ + c * width_ + col] =
                f.IsWhite(g.first_id + r * g.tag_cols + c, col, width_ - 1 - row) ? 1 : 0;
          }
        }
      }
    }
    return true;
  }

  // Board point seen along the homogeneous ray r (any positive multiple of the unit ray, e.g.
  // (x, y, 1) in front): h = [r1 r2 t]^-1 r; the hit is in front iff h.z > 0 (r = lambda
  // [r1 r2 t] (bx, by, 1) with lambda = 1 / h.z > 0, whatever the sign of r.z). False if the ray
  // misses the board's plane in front of the camera or lands outside the board; else *bx, *by (m)
  // and *depth = 1 / h.z (the distance along r in units of |r|: comparable between boards on the
  // same r; the camera z for r = (x, y, 1)).
  bool ToBoard(const Eigen::Vector3d& r, double* bx, double* by, double* depth) const {
    if (!visible_) return false;
    const Eigen::Matrix3d& m = board_from_ray_;
    // Written out in this order (r.z() = 1 for the plane's rays: their hits are those of the
    // two-coordinate form bit for bit).
    const double hz = m(2, 0) * r.x() + m(2, 1) * r.y() + m(2, 2) * r.z();
    if (!(hz > 0)) return false;
    const double inv = 1.0 / hz;
    *bx = (m(0, 0) * r.x() + m(0, 1) * r.y() + m(0, 2) * r.z()) * inv;
    *by = (m(1, 0) * r.x() + m(1, 1) * r.y() + m(1, 2) * r.z()) * inv;
    *depth = inv;
    return *bx >= min_ && *by >= min_ && *bx <= max_x_ && *by <= max_y_;
  }

  // Shade of board point (bx, by): 0 black, 1 white, kOffBoard outside the board.
  int Shade(double bx, double by) const { return ShadeAndCell(bx, by, nullptr); }

  // Shade, and on the board (when `cell` is given) the cell the point falls in as two 16-bit keys
  // (column << 16 | row), each non-decreasing in its coordinate: no cell line of an axis lies
  // between two points whose keys for it agree. A key numbers tag t's bitmap column (row) k, t in
  // [-1, tags] (on the board: its margin is less than a pitch), k in [0, width] (the gap after a
  // bitmap shares its last key; the corner squares' sides are lines of the tags' black squares).
  int ShadeAndCell(double bx, double by, uint32_t* cell) const {
    if (bx < min_ || by < min_ || bx > max_x_ || by > max_y_) return kOffBoard;
    // The tag whose full bitmap (reference square plus border_start cells around) may hold b.
    const int c = FloorSmall((bx + start_ * cell_) * inv_pitch_);
    const int r = FloorSmall((by + start_ * cell_) * inv_pitch_);
    const int col = FloorSmall((bx - c * pitch_) * inv_cell_) + start_;
    const int row = FloorSmall((by - r * pitch_) * inv_cell_) + start_;
    if (cell) *cell = AxisKey(c, col, cols_) << 16 | AxisKey(r, row, rows_);
    if (corner_squares_) {
      // Square (i, j) spans [i p - g, i p) x [j p - g, j p) (sim/target.h).
      const double u = bx + gap_, v = by + gap_;
      const int i = FloorSmall(u * inv_pitch_), j = FloorSmall(v * inv_pitch_);
      if (i >= 0 && j >= 0 && i <= cols_ && j <= rows_ && u - i * pitch_ < gap_ &&
          v - j * pitch_ < gap_) {
        return 0;
      }
    }
    if (c < 0 || r < 0 || c >= cols_ || r >= rows_) return 1;
    if (col < 0 || row < 0 || col >= width_ || row >= width_) return 1;
    return cells_[(static_cast<size_t>(r) * width_ + row) * cols_ * width_ + c * width_ + col];
  }

  // Mean of lut[Shade + 1] (off-board, black, white) over a pixel whose footprint on this board is
  // `quad` (the board points of its corners (0, 0), (1, 0), (1, 1), (0, 1)): the shade is constant
  // between the lines of LinesCrossing, so the quad is cut along them (ClipToHalfPlane) and each
  // piece weighs its area in the pixel (PixelFromBoard). False, *mean untouched, when an axis holds
  // more lines than AxisLines takes (cells far below a pixel) or the quad is degenerate (a board
  // seen edge-on): the caller samples instead.
  bool MeanOverFootprint(const std::array<Eigen::Vector2d, 4>& quad,
                         const std::array<float, 3>& lut, float* mean) const {
    // Local coordinates about the first corner: no cancellation in the areas.
    const Eigen::Vector2d& origin = quad[0];
    SmallPolygon footprint;
    footprint.n = 4;
    Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
    for (int k = 0; k < 4; ++k) {
      footprint.v[k] = quad[k] - origin;
      lo = lo.cwiseMin(footprint.v[k]);
      hi = hi.cwiseMax(footprint.v[k]);
    }
    PixelFromBoard pixel;
    if (!pixel.Init(footprint)) return false;
    std::array<AxisLines, 2> lines;
    for (int axis = 0; axis < 2; ++axis) {
      LinesCrossing(axis, origin[axis] + lo[axis], origin[axis] + hi[axis], &lines[axis]);
      if (lines[axis].full) return false;
      for (int k = 0; k < lines[axis].n; ++k) lines[axis].at[k] -= origin[axis];
    }
    std::array<double, 3> weight = {0, 0, 0};  // Twice each shade's area in the pixel.
    // Each piece shaded at its centroid, never at a corner of the footprint: a corner may lie on a
    // line of the other axis and see the cell beyond the footprint.
    SmallPolygon slab_buffer, slab_scratch, piece_buffer, piece_scratch;
    for (int i = 0; i <= lines[0].n; ++i) {
      const SmallPolygon& slab =
          ClipBetween(footprint, 0, lines[0], i, &slab_buffer, &slab_scratch);
      if (slab.n < 3) continue;
      for (int j = 0; j <= lines[1].n; ++j) {
        const SmallPolygon& piece =
            ClipBetween(slab, 1, lines[1], j, &piece_buffer, &piece_scratch);
        if (piece.n < 3) continue;
        const Eigen::Vector2d inside = origin + Centroid(piece);
        weight[Shade(inside.x(), inside.y()) + 1] += pixel.TwicePixelArea(piece);
      }
    }
    return WeightedMean(weight, lut, mean);
  }

  // Pixel-corner box [i0, i1] x [j0, j1] outside which the board cannot be seen: the projection of
  // its outline sampled densely, padded by 2 px; the whole image when the board may hold rays the
  // lens does not map one-to-one: an outline point outside the lens's valid region (radtan,
  // equidistant: z <= 0) or where the distortion folds over (d r_d / d r <= 0), or, for the
  // omnidirectional families, a board that holds the backward axis (it could then hold the whole
  // invalid cap about it, the outline staying valid).
  void ComputeImageBounds(const CameraIntrinsics& k, const Rigid3& cam_from_board, int width,
                          int height) {
    i0_ = 0, j0_ = 0, i1_ = width, j1_ = height;
    if (!visible_) {
      i0_ = 1, i1_ = 0;  // Empty.
      return;
    }
    constexpr int kSamplesPerEdge = 64;
    constexpr double kPadPx = 2.0;
    const bool plane = IsPlaneFamily(k.family);
    double bx = 0, by = 0, depth = 0;
    if (!plane && ToBoard(Eigen::Vector3d(0, 0, -1), &bx, &by, &depth)) return;
    double u_min = 1e300, u_max = -1e300, v_min = 1e300, v_max = -1e300;
    const double xs[2] = {min_, max_x_}, ys[2] = {min_, max_y_};
    for (int e = 0; e < 4; ++e) {
      for (int s = 0; s <= kSamplesPerEdge; ++s) {
        const double f = static_cast<double>(s) / kSamplesPerEdge;
        const Eigen::Vector3d point_in_board =
            e < 2 ? Eigen::Vector3d(xs[0] + f * (xs[1] - xs[0]), ys[e], 0)
                  : Eigen::Vector3d(xs[e - 2], ys[0] + f * (ys[1] - ys[0]), 0);
        Eigen::Vector2d pixel;
        if (!ProjectUnfolded(k, cam_from_board * point_in_board, &pixel)) return;
        u_min = std::min(u_min, pixel.x()), u_max = std::max(u_max, pixel.x());
        v_min = std::min(v_min, pixel.y()), v_max = std::max(v_max, pixel.y());
      }
    }
    // Corner (i, j) is at pixel coordinates (i - 0.5, j - 0.5); a lens without an image circle may
    // put an outline point arbitrarily far (clamped before the conversion to int).
    auto corner = [](double px, int size) { return std::clamp(px + 0.5, -8.0, size + 8.0); };
    i0_ = std::max(0, FastFloor(corner(u_min, width) - kPadPx));
    i1_ = std::min(width, FastFloor(corner(u_max, width) + kPadPx) + 1);
    j0_ = std::max(0, FastFloor(corner(v_min, height) - kPadPx));
    j1_ = std::min(height, FastFloor(corner(v_max, height) + kPadPx) + 1);
  }
  bool Covers(int i, int j) const { return i >= i0_ && i <= i1_ && j >= j0_ && j <= j1_; }
  int i0() const { return i0_; }
  int i1() const { return i1_; }
  int j0() const { return j0_; }
  int j1() const { return j1_; }

 private:
  // The mean of its vertices: inside a convex polygon.
  static Eigen::Vector2d Centroid(const SmallPolygon& p) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int k = 0; k < p.n; ++k) sum += p.v[k];
    return p.n > 0 ? Eigen::Vector2d(sum / p.n) : sum;
  }

  // sum_s lut[s] weight[s] / sum_s weight[s]; false when the weights sum to no area.
  static bool WeightedMean(const std::array<double, 3>& weight, const std::array<float, 3>& lut,
                           float* mean) {
    const double total = weight[0] + weight[1] + weight[2];
    if (!(std::abs(total) > 0)) return false;
    *mean =
        static_cast<float>((lut[0] * weight[0] + lut[1] * weight[1] + lut[2] * weight[2]) / total);
    return true;
  }

  uint32_t AxisKey(int tag, int k, int tags) const {
    return static_cast<uint32_t>((std::clamp(tag, -1, tags) + 1) * (width_ + 1) +
                                 std::clamp(k, 0, width_));
  }

  // The lines coordinate `axis` = const (0: x, 1: y) in (lo, hi) on which Shade may change: the
  // board's outline, the cell lines of every tag bitmap that reaches the interval (tag t's cells
  // start at t p - start cell), the corner squares' sides (i p - g and i p); ascending.
  void LinesCrossing(int axis, double lo, double hi, AxisLines* lines) const {
    const int tags = axis == 0 ? cols_ : rows_;
    lines->Add(min_, lo, hi);
    lines->Add(axis == 0 ? max_x_ : max_y_, lo, hi);
    const double first = -start_ * cell_, span = width_ * cell_;
    const int t0 = std::max(0, FloorSmall((lo - first - span) * inv_pitch_));
    const int t1 = std::min(tags - 1, FloorSmall((hi - first) * inv_pitch_));
    for (int t = t0; t <= t1 && !lines->full; ++t) {
      const double start = t * pitch_ + first;
      const int k0 = std::max(0, FloorSmall((lo - start) * inv_cell_));
      const int k1 = std::min(width_, FloorSmall((hi - start) * inv_cell_) + 1);
      for (int k = k0; k <= k1; ++k) lines->Add(start + k * cell_, lo, hi);
    }
    if (corner_squares_) {
      const int i0 = std::max(0, FloorSmall(lo * inv_pitch_));
      const int i1 = std::min(tags, FloorSmall((hi + gap_) * inv_pitch_) + 1);
      for (int i = i0; i <= i1; ++i) {
        lines->Add(i * pitch_ - gap_, lo, hi);
        lines->Add(i * pitch_, lo, hi);
      }
    }
    for (int k = 1; k < lines->n; ++k) {  // Insertion sort: a few lines.
      for (int m = k; m > 0 && lines->at[m] < lines->at[m - 1]; --m) {
        std::swap(lines->at[m], lines->at[m - 1]);
      }
    }
  }

  // The part of `in` between lines k - 1 and k of `lines` (unbounded below for k = 0, above for
  // k = lines.n): `in` itself when no line bounds it, else in *out or *scratch.
  static const SmallPolygon& ClipBetween(const SmallPolygon& in, int axis, const AxisLines& lines,
                                         int k, SmallPolygon* out, SmallPolygon* scratch) {
    const SmallPolygon* from = &in;
    if (k > 0) {
      ClipToHalfPlane(*from, axis, lines.at[k - 1], true, scratch);
      from = scratch;
    }
    if (k == lines.n) return *from;
    ClipToHalfPlane(*from, axis, lines.at[k], false, out);
    return *out;
  }

  bool visible_ = false;
  Eigen::Matrix3d board_from_ray_;
  double cell_ = 0, inv_cell_ = 0, pitch_ = 0, inv_pitch_ = 0, min_ = 0, max_x_ = 0, max_y_ = 0;
  double gap_ = 0;  // White between two tags' black squares (m).
  bool corner_squares_ = false;
  int start_ = 0, width_ = 0, cols_ = 0, rows_ = 0;
  int i0_ = 0, i1_ = -1, j0_ = 0, j1_ = -1;  // Pixel-corner bounds, inclusive.
  std::vector<uint8_t> cells_;
};

// Position in the pixel (from its top-left corner, in [0, 1)^2) of sample (a, b) of n x n: a
// regular grid sheared by one sub-cell, so that the n^2 samples have n^2 distinct x and n^2
// distinct y offsets (an "n-rooks" pattern). A plain n x n grid sees an axis-aligned edge in only
// n + 1 levels, i.e. positions quantised to 1/n px (0.125 px error at n = 4); this one in n^2 + 1.
inline Eigen::Vector2d SampleOffset(int a, int b, int n) {
  const double nn = static_cast<double>(n) * n;
  return {(a * n + b + 0.5) / nn, (b * n + a + 0.5) / nn};
}

// Sum of sample(a, b) over the n x n samples of a pixel (a = column, b = row).
template <typename Sample>
float SumSamples(int n, const Sample& sample) {
  float sum = 0;
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a < n; ++a) sum += sample(a, b);
  }
  return sum;
}

// Nearest board hit along a homogeneous ray: kOffBoard or 2 * board + (1 if white).
inline int TraceBoards(const std::vector<BoardShader>& boards, const Eigen::Vector3d& ray) {
  double nearest = std::numeric_limits<double>::infinity();
  int hit = kOffBoard;
  for (size_t i = 0; i < boards.size(); ++i) {
    double bx = 0, by = 0, depth = 0;
    if (!boards[i].ToBoard(ray, &bx, &by, &depth) || depth >= nearest) continue;
    nearest = depth;
    hit = 2 * static_cast<int>(i) + boards[i].Shade(bx, by);
  }
  return hit;
}

}  // namespace render_internal
}  // namespace calibench
