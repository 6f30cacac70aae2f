// The renderer's inner pieces (sim/render.h; render.cc's FrameRenderer uses them): one board of a
// frame as seen along rays (its ray -> board homography, the shade of a board point from the tag
// bitmaps and Kalibr's corner squares, its pixel bounds), how the ray table holds a ray in two
// numbers, and the n x n sample pattern of a pixel. Internal to sim/: not part of its API.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
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
// z = 1, rays in front only (radtan and equidistant); kStereographic: (x, y) = (X, Y) / (|P| + Z),
// every ray but the backward axis (the omnidirectional families, whose rays reach past 90 deg).
enum class RaySpace { kPlane, kStereographic };

inline RaySpace RaySpaceOf(LensFamily family) {
  switch (family) {
    case LensFamily::kRadTan:
    case LensFamily::kEquidistant:
      return RaySpace::kPlane;
    case LensFamily::kUnified:
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere:
      return RaySpace::kStereographic;
  }
  return RaySpace::kStereographic;
}
inline bool IsPlaneFamily(LensFamily family) { return RaySpaceOf(family) == RaySpace::kPlane; }

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
    if (g.first_id + g.NumTags() > f.num_codes()) {
      if (why)
        *why = g.family + " has only " + std::to_string(f.num_codes()) +
               " codes, the grid needs ids up to " + std::to_string(g.first_id + g.NumTags() - 1);
      return false;
    }
    Eigen::Matrix3d plane;  // [r1 r2 t]: board (bx, by, 1) -> camera ray.
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
  int Shade(double bx, double by) const {
    if (bx < min_ || by < min_ || bx > max_x_ || by > max_y_) return kOffBoard;
    if (corner_squares_) {
      // Square (i, j) spans [i p - g, i p) x [j p - g, j p) (sim/target.h). Its edges are edges
      // of the tags' black squares too: AxisKeys needs no new keys.
      const double u = bx + gap_, v = by + gap_;
      const int i = FloorSmall(u * inv_pitch_), j = FloorSmall(v * inv_pitch_);
      if (i >= 0 && j >= 0 && i <= cols_ && j <= rows_ && u - i * pitch_ < gap_ &&
          v - j * pitch_ < gap_) {
        return 0;
      }
    }
    // The tag whose full bitmap (reference square plus border_start cells around) may hold b.
    const int c = FloorSmall((bx + start_ * cell_) * inv_pitch_);
    const int r = FloorSmall((by + start_ * cell_) * inv_pitch_);
    if (c < 0 || r < 0 || c >= cols_ || r >= rows_) return 1;
    const int col = FloorSmall((bx - c * pitch_) * inv_cell_) + start_;
    const int row = FloorSmall((by - r * pitch_) * inv_cell_) + start_;
    if (col < 0 || row < 0 || col >= width_ || row >= width_) return 1;
    return cells_[(static_cast<size_t>(r) * width_ + row) * cols_ * width_ + c * width_ + col];
  }

  // Keys of the column and row a board point falls in, non-decreasing in bx and in by: two points
  // with equal x keys see no vertical cell edge between them.
  void AxisKeys(double bx, double by, int* kx, int* ky) const {
    *kx = AxisKey(bx, max_x_, cols_);
    *ky = AxisKey(by, max_y_, rows_);
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
        const Eigen::Vector3d p = cam_from_board * point_in_board;
        if (plane) {
          if (!(p.z() > 1e-9)) return;
          const double r2 = (p.x() * p.x() + p.y() * p.y()) / (p.z() * p.z());
          if (!k.DistortionIsMonotoneAt(r2)) return;
        } else if (!k.DistortionIsMonotoneAlong(p)) {
          return;
        }
        Eigen::Vector2d pixel;
        if (!ProjectPoint(k, p, &pixel)) return;
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
  int AxisKey(double x, double max, int tags) const {
    if (x < min_) return std::numeric_limits<int>::min();
    if (x > max) return std::numeric_limits<int>::max();
    const int c = std::clamp(FloorSmall((x + start_ * cell_) * inv_pitch_), -1, tags);
    const int col = std::clamp(FloorSmall((x - c * pitch_) * inv_cell_) + start_, 0, width_);
    return c * (width_ + 1) + col;
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

// Sum of sample(a, b) over the n x n samples of a pixel (a = column, b = row). With
// `rows_are_simple`, the caller guarantees that the shade cannot change and change back along a
// row of samples (the edges crossing the pixel are parallel lines at least a pixel apart): a row
// whose end samples agree is then filled without sampling inside.
template <typename Sample>
float SumSamples(int n, bool rows_are_simple, const Sample& sample) {
  float sum = 0;
  for (int b = 0; b < n; ++b) {
    if (!rows_are_simple || n <= 2) {
      for (int a = 0; a < n; ++a) sum += sample(a, b);
      continue;
    }
    const float first = sample(0, b), end = sample(n - 1, b);
    sum += first + end;
    if (first == end) {
      sum += (n - 2) * first;
      continue;
    }
    for (int a = 1; a < n - 1; ++a) sum += sample(a, b);
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
