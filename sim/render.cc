#include "sim/render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/image_filters.h"

namespace calibench {
namespace {

constexpr int kOffBoard = -1;
constexpr int kMaxBlurGrid = 8;  // Sub-pixels per side of the automatic blur grid.
constexpr double kMaxFinePixels = 16e6;

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

RaySpace RaySpaceOf(LensFamily family) {
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
bool IsPlaneFamily(LensFamily family) { return RaySpaceOf(family) == RaySpace::kPlane; }

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
int TraceBoards(const std::vector<BoardShader>& boards, const Eigen::Vector3d& ray) {
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

}  // namespace

bool RenderOptions::Check(std::string* why) const {
  std::string msg;
  if (width < 1 || height < 1) msg = "image size must be positive";
  if (width > kMaxRenderSide || height > kMaxRenderSide ||
      static_cast<double>(width) * height > kMaxRenderPixels) {
    msg = "image size " + std::to_string(width) + " x " + std::to_string(height) +
          " is beyond the renderer's bound (" + std::to_string(kMaxRenderSide) +
          " px per side, 64 Mpx; its ray table takes 16 bytes per pixel corner)";
  }
  if (supersample < 1 || supersample > 64) msg = "supersample must lie in [1, 64]";
  if (!(blur_sigma_px >= 0)) msg = "blur_sigma_px must be >= 0";
  if (blur_grid < 0 || blur_grid > 16) msg = "blur_grid must lie in [0, 16] (0: automatic)";
  if (!(noise_sigma_gray >= 0)) msg = "noise_sigma_gray must be >= 0";
  for (double g : {background_gray, black_gray, white_gray}) {
    if (!(g >= 0 && g <= 255)) msg = "gray levels must lie in [0, 255]";
  }
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

namespace {

// The ray of pixel-corner position (u, v) (pixel coordinates) of a distorted camera, in the table's
// form: (x, y) on the plane z = 1 for the families that see only z > 0, stereographic coordinates
// for the omnidirectional ones; NaN outside the lens's valid region.
Eigen::Vector2d TableRay(const CameraIntrinsics& intrinsics, const Eigen::Matrix3d& a_inv, double u,
                         double v) {
  Eigen::Vector2d xy = (a_inv * Eigen::Vector3d(u, v, 1.0)).head<2>();
  bool valid = false;
  if (IsPlaneFamily(intrinsics.family)) {
    valid = UndistortNormalized(intrinsics, Eigen::Vector2d(xy), &xy);
  } else {
    Eigen::Vector3d ray;
    valid = RayOfDistorted(intrinsics, xy, &ray);  // UnprojectToRay, A^-1 at hand.
    if (valid) xy = Stereographic(ray);
  }
  if (!valid) xy.setConstant(std::numeric_limits<double>::quiet_NaN());
  return xy;
}

// The rays of the (w + 1) x (h + 1) pixel corners, row-major.
std::vector<Eigen::Vector2d> RayTable(const CameraIntrinsics& intrinsics, int w, int h) {
  const Eigen::Matrix3d a_inv = intrinsics.Matrix().inverse();
  std::vector<Eigen::Vector2d> table(static_cast<size_t>(w + 1) * (h + 1));
  for (int j = 0; j <= h; ++j) {
    for (int i = 0; i <= w; ++i) {
      table[static_cast<size_t>(j) * (w + 1) + i] = TableRay(intrinsics, a_inv, i - 0.5, j - 0.5);
    }
  }
  return table;
}

// The corner rays of a grid m times finer, interpolated bilinearly between the pixel corners'
// (as the renderer's samples inside a pixel are: below 1e-3 px with |k1| <= 0.3), and computed
// exactly (`finer`: the finer grid's camera) where a pixel corner has no valid ray. m^2 times
// fewer inversions of the lens than a table built for the finer grid.
std::vector<Eigen::Vector2d> FinerRayTable(const std::vector<Eigen::Vector2d>& coarse,
                                           const CameraIntrinsics& finer, int w, int h, int m) {
  const Eigen::Matrix3d a_inv = finer.Matrix().inverse();
  const size_t stride = static_cast<size_t>(w) * m + 1;
  std::vector<Eigen::Vector2d> table(stride * (static_cast<size_t>(h) * m + 1));
  for (int jj = 0; jj <= h * m; ++jj) {
    const int j = std::min(jj / m, h - 1);
    const double fb = static_cast<double>(jj - j * m) / m;
    for (int ii = 0; ii <= w * m; ++ii) {
      const int i = std::min(ii / m, w - 1);
      const double fa = static_cast<double>(ii - i * m) / m;
      const size_t k00 = static_cast<size_t>(j) * (w + 1) + i, k01 = k00 + w + 1;
      const Eigen::Vector2d ray = (1 - fb) * ((1 - fa) * coarse[k00] + fa * coarse[k00 + 1]) +
                                  fb * ((1 - fa) * coarse[k01] + fa * coarse[k01 + 1]);
      table[static_cast<size_t>(jj) * stride + ii] =
          ray.allFinite() ? ray : TableRay(finer, a_inv, ii - 0.5, jj - 0.5);
    }
  }
  return table;
}

}  // namespace

std::unique_ptr<FrameRenderer> FrameRenderer::Create(const CameraIntrinsics& intrinsics,
                                                     const RenderOptions& options,
                                                     std::string* why) {
  if (!options.Check(why) || !intrinsics.Check(why)) return nullptr;
  std::unique_ptr<FrameRenderer> r(new FrameRenderer());
  r->intrinsics_ = intrinsics;
  r->options_ = options;
  const int w = options.width, h = options.height;
  if (options.blur_sigma_px > 0) {
    int m = options.blur_grid > 0
                ? options.blur_grid
                : std::min(kMaxBlurGrid, static_cast<int>(std::ceil(3 / options.blur_sigma_px)));
    // The finer grid's ray table and buffers take ~30 bytes a sub-pixel: at most kMaxFinePixels.
    while (m > 1 && static_cast<double>(w) * m * h * m > kMaxFinePixels) --m;
    if (m > 1) {
      RenderOptions fine = options;
      fine.width = w * m;
      fine.height = h * m;
      fine.blur_sigma_px = 0;
      fine.noise_sigma_gray = 0;

      std::unique_ptr<FrameRenderer> finer(new FrameRenderer());
      finer->intrinsics_ = FinerCamera(intrinsics, m);
      finer->options_ = fine;
      if (intrinsics.IsDistorted()) {
        finer->corner_rays_ =
            FinerRayTable(RayTable(intrinsics, w, h), finer->intrinsics_, w, h, m);
      }
      r->fine_ = std::move(finer);
      r->fine_grid_ = m;
      return r;  // The pixels' own ray table is not used.
    }
  }
  if (intrinsics.IsDistorted()) r->corner_rays_ = RayTable(intrinsics, w, h);
  // Without distortion rays are affine in the pixel: ShadePixels computes them.
  return r;
}

bool FrameRenderer::Render(const std::vector<BoardView>& views, Rng* noise_rng, GrayImage* image,
                           std::string* why, const CameraIntrinsics* camera_now) const {
  const RenderOptions& o = options_;
  Eigen::Matrix3d ray_map = Eigen::Matrix3d::Identity();
  const CameraIntrinsics& camera = camera_now ? *camera_now : intrinsics_;
  if (camera_now != nullptr && *camera_now != intrinsics_) {
    if (camera_now->IsDistorted() || intrinsics_.IsDistorted()) {
      const auto renderer = Create(*camera_now, options_, why);
      return renderer && renderer->Render(views, noise_rng, image, why);
    }
    // The same map for a finer grid: (S A_now)^-1 (S A) = A_now^-1 A.
    ray_map = camera_now->Matrix().inverse() * intrinsics_.Matrix();
  }
  if (o.noise_sigma_gray > 0 && noise_rng == nullptr) {
    if (why) *why = "noise_sigma_gray > 0 needs a random generator";
    return false;
  }
  const int w = o.width, h = o.height;
  thread_local std::vector<float> values;
  std::array<int, 4> box;  // x0, x1, y0, y1 of the boards.
  if (fine_) {
    const int m = fine_grid_;
    thread_local std::vector<float> fine_values;
    if (!fine_->ShadePixels(views, ray_map, FinerCamera(camera, m), &fine_values, &box, why)) {
      return false;
    }
    BlurNearBoardsAndSumBlocks(o.blur_sigma_px * m, w, h, m, box, fine_values, &values);
  } else {
    if (!ShadePixels(views, ray_map, camera, &values, &box, why)) return false;
    if (o.blur_sigma_px > 0) BlurNearBoards(o.blur_sigma_px, w, h, box, &values);
  }
  image->width = w;
  image->height = h;
  image->pixels.resize(values.size());
  if (o.noise_sigma_gray > 0) AddImageNoise(o.noise_sigma_gray, w, h, noise_rng, &values);
  for (size_t k = 0; k < values.size(); ++k) {  // Round half up (the values are >= 0).
    image->pixels[k] =                          // NOLINTNEXTLINE(bugprone-incorrect-roundings)
        static_cast<uint8_t>(std::clamp(values[k], 0.0f, 255.0f) + 0.5f);
  }
  return true;
}

namespace {

// A pixel corner's ray in the table's coordinates (RaySpace), lifted to a homogeneous ray by
// LiftRay: from the table, or without distortion A^-1 (i - 0.5, j - 0.5, 1), as in the table.
struct CornerRays {
  const std::vector<Eigen::Vector2d>& table;  // Empty without distortion.
  const Eigen::Matrix3d& a_inv;
  size_t stride;  // w + 1.
  Eigen::Vector2d operator()(int i, int j) const {
    return !table.empty()
               ? table[static_cast<size_t>(j) * stride + i]
               : Eigen::Vector2d((a_inv * Eigen::Vector3d(i - 0.5, j - 0.5, 1.0)).head<2>());
  }
};

// Pass 1's result per pixel corner, row-major over (w + 1) x (h + 1): the hit (kOffBoard or
// 2 * board + (1 if white)) and where on that board.
struct CornerHits {
  std::vector<int16_t>& hit;
  std::vector<Eigen::Vector2f>& in_board;  // Float: 1e-7 m on a 1 m board.
  size_t stride;
};

// Pass 1: what each pixel corner sees (the nearest board along its ray), and where on it.
void TraceCorners(const std::vector<BoardShader>& boards, const CornerRays& rays, RaySpace space,
                  int h, CornerHits* hits) {
  thread_local std::vector<double> depths;  // Per column: the nearest board's depth on this row.
  depths.resize(hits->stride);
  for (int j = 0; j <= h; ++j) {
    std::fill(depths.begin(), depths.end(), std::numeric_limits<double>::infinity());
    for (size_t b = 0; b < boards.size(); ++b) {
      const BoardShader& board = boards[b];
      if (j < board.j0() || j > board.j1()) continue;
      for (int i = board.i0(); i <= board.i1(); ++i) {
        const size_t k = j * hits->stride + i;
        const Eigen::Vector3d ray = LiftRay(space, rays(i, j));
        double bx = 0, by = 0, depth = 0;
        if (!board.ToBoard(ray, &bx, &by, &depth) || !(depth < depths[i])) continue;
        depths[i] = depth;
        hits->hit[k] = static_cast<int16_t>(2 * b + board.Shade(bx, by));
        hits->in_board[k] = Eigen::Vector2f(bx, by);
      }
    }
  }
}

// Whether the pixel whose top-left corner is k00 sees only `board`: its four corners hit it and no
// other board's bounds cover the pixel (i, j).
bool SeesOneBoard(const std::vector<BoardShader>& boards, const CornerHits& hits, size_t k00, int i,
                  int j) {
  const std::vector<int16_t>& c = hits.hit;
  const size_t k01 = k00 + hits.stride;
  const int board = c[k00] / 2;
  bool one_board = c[k00] >= 0 && c[k00 + 1] / 2 == board && c[k01] / 2 == board &&
                   c[k01 + 1] >= 0 && c[k01 + 1] / 2 == board && c[k00 + 1] >= 0 && c[k01] >= 0;
  for (size_t b = 0; one_board && b < boards.size(); ++b) {
    if (static_cast<int>(b) != board && boards[b].Covers(i, j)) one_board = false;
  }
  return one_board;
}

// The n x n samples' sum of a pixel on one board, their board points interpolated between the
// corners' (a homography is affine to 1e-6 px over one pixel). lut: off-board, black, white.
float SumOnOneBoard(const BoardShader& shader, const std::array<float, 3>& lut,
                    const CornerHits& hits, size_t k00, const std::vector<Eigen::Vector2d>& offsets,
                    int n) {
  const size_t k01 = k00 + hits.stride;
  // b(fa, fb) = p + fa u + fb v + fa fb q over the pixel, from its corners' board points.
  const Eigen::Vector2d p = hits.in_board[k00].cast<double>();
  const Eigen::Vector2d u = hits.in_board[k00 + 1].cast<double>() - p;
  const Eigen::Vector2d v = hits.in_board[k01].cast<double>() - p;
  const Eigen::Vector2d q = hits.in_board[k01 + 1].cast<double>() - p - u - v;
  // Cell-edge lines of one direction only cross the pixel when all four corners share the
  // column key or the row key (keys are monotone, the footprint is in the corners' hull).
  int kx[4], ky[4];
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector2f& corner = hits.in_board[c < 2 ? k00 + c : k01 + c - 2];
    shader.AxisKeys(corner.x(), corner.y(), &kx[c], &ky[c]);
  }
  const bool one_direction = (kx[0] == kx[1] && kx[0] == kx[2] && kx[0] == kx[3]) ||
                             (ky[0] == ky[1] && ky[0] == ky[2] && ky[0] == ky[3]);
  return SumSamples(n, one_direction, [&](int a, int b) {
    const Eigen::Vector2d& f = offsets[b * n + a];
    const double fa = f.x(), fb = f.y();
    const Eigen::Vector2d point = p + fa * u + fb * v + fa * fb * q;
    return lut[shader.Shade(point.x(), point.y()) + 1];
  });
}

// The pixel box [x0, x1) x [y0, y1) of the visible boards (empty: x0 = w, y0 = h).
std::array<int, 4> BoardsBox(const std::vector<BoardShader>& boards, int w, int h) {
  int x0 = w, x1 = 0, y0 = h, y1 = 0;
  for (const BoardShader& board : boards) {
    if (board.i0() > board.i1() || board.j0() > board.j1()) continue;  // Not visible.
    x0 = std::min(x0, board.i0()), x1 = std::max(x1, board.i1());
    y0 = std::min(y0, board.j0()), y1 = std::max(y1, board.j1());
  }
  return {x0, x1, y0, y1};
}

// The n x n samples' sum of a pixel whose corners see more than one board or a board's edge: each
// sample traced to the nearest board, its ray interpolated between the corners' or, where a corner
// has no ray (outside the lens's valid region), unprojected by sample_ray(u, v, &ray).
struct TracedPixel {
  int i, j;
  const CornerRays& rays;
  const std::vector<BoardShader>& boards;
  const std::vector<float>& gray_of;  // Gray level of hit h at h + 1 (h = kOffBoard: -1).
  const std::vector<Eigen::Vector2d>& offsets;
  RaySpace space;
};
template <typename SampleRayFn>
float SumTracedSamples(const TracedPixel& pixel, int n, const SampleRayFn& sample_ray) {
  const int i = pixel.i, j = pixel.j;
  const Eigen::Vector2d r00 = pixel.rays(i, j), r10 = pixel.rays(i + 1, j);
  const Eigen::Vector2d r01 = pixel.rays(i, j + 1), r11 = pixel.rays(i + 1, j + 1);
  const bool exact = std::isnan(r00.x() + r10.x() + r01.x() + r11.x());
  const auto gray = [&](int hit) { return pixel.gray_of[hit + 1]; };
  float sum = 0;
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a < n; ++a) {
      const Eigen::Vector2d& f = pixel.offsets[b * n + a];
      const double fa = f.x(), fb = f.y();
      if (exact) {
        Eigen::Vector3d ray;
        if (!sample_ray(i - 0.5 + fa, j - 0.5 + fb, &ray)) {
          sum += gray(kOffBoard);
          continue;
        }
        sum += gray(TraceBoards(pixel.boards, ray));
        continue;
      }
      const Eigen::Vector2d q =
          (1 - fb) * ((1 - fa) * r00 + fa * r10) + fb * ((1 - fa) * r01 + fa * r11);
      sum += gray(TraceBoards(pixel.boards, LiftRay(pixel.space, q)));
    }
  }
  return sum;
}

}  // namespace

bool FrameRenderer::ShadePixels(const std::vector<BoardView>& views, const Eigen::Matrix3d& ray_map,
                                const CameraIntrinsics& camera, std::vector<float>* values_out,
                                std::array<int, 4>* boards_box, std::string* why) const {
  const RenderOptions& o = options_;
  std::vector<BoardShader> boards(views.size());
  for (size_t b = 0; b < views.size(); ++b) {
    if (!views[b].family) {
      if (why) *why = "board family '" + views[b].grid.family + "' has no TagFamily";
      return false;
    }
    if (!boards[b].Init(views[b], ray_map, why)) return false;
  }
  const int w = o.width, h = o.height, n = o.supersample;
  for (size_t b = 0; b < views.size(); ++b) {
    boards[b].ComputeImageBounds(camera, views[b].cam_from_board, w, h);
  }
  // Gray level of a hit: gray_of[hit + 1], hit = kOffBoard or 2 * board + (1 if white).
  std::vector<float> gray_of(2 * boards.size() + 1, static_cast<float>(o.background_gray));
  for (size_t b = 0; b < boards.size(); ++b) {
    gray_of[2 * b + 1] = static_cast<float>(o.black_gray);
    gray_of[2 * b + 2] = static_cast<float>(o.white_gray);
  }
  // Pass 1, pixel corners: what each sees, and where on its board.
  const size_t stride = w + 1;
  // Per-thread scratch buffers, reused from frame to frame (no page faults per frame).
  thread_local std::vector<int16_t> corners;
  thread_local std::vector<Eigen::Vector2f> corner_in_board;
  const size_t num_corners = static_cast<size_t>(w + 1) * (h + 1);
  corners.assign(num_corners, kOffBoard);
  corner_in_board.resize(num_corners);
  const Eigen::Matrix3d a_inv = intrinsics_.Matrix().inverse();
  const CornerRays corner_rays{corner_rays_, a_inv, stride};
  CornerHits hits{corners, corner_in_board, stride};
  const RaySpace space = RaySpaceOf(intrinsics_.family);
  TraceCorners(boards, corner_rays, space, h, &hits);
  // Pass 2, pixels: one shade if the four corners agree, else n x n samples: interpolated on the
  // board when the pixel sees one board only (SumOnOneBoard), traced otherwise.
  std::vector<Eigen::Vector2d> offsets(static_cast<size_t>(n) * n);
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a < n; ++a) offsets[b * n + a] = SampleOffset(a, b, n);
  }
  const auto sample_ray = [&](double u, double v, Eigen::Vector3d* ray) {
    return SampleRay(a_inv, u, v, ray);
  };
  std::vector<float>& values = *values_out;
  values.resize(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j) {
    // Pixels with no board's bounds at any corner see the background.
    int i_begin = w, i_end = 0;
    for (const BoardShader& board : boards) {
      if (j + 1 < board.j0() || j > board.j1()) continue;
      i_begin = std::min(i_begin, std::max(0, board.i0() - 1));
      i_end = std::max(i_end, std::min(w, board.i1() + 1));
    }
    float* row = values.data() + static_cast<size_t>(j) * w;
    std::fill(row, row + w, gray_of[kOffBoard + 1]);
    const int16_t* top = corners.data() + j * stride;
    const int16_t* bottom = top + stride;
    for (int i = i_begin; i < i_end; ++i) {
      const int c00 = top[i];
      if (c00 == top[i + 1] && c00 == bottom[i] && c00 == bottom[i + 1]) {
        row[i] = gray_of[c00 + 1];
        continue;
      }
      const size_t k00 = j * stride + i;
      float sum = 0;
      if (SeesOneBoard(boards, hits, k00, i, j)) {
        const int board = c00 / 2;
        const std::array<float, 3> lut = {gray_of[kOffBoard + 1], gray_of[2 * board + 1],
                                          gray_of[2 * board + 2]};
        sum = SumOnOneBoard(boards[board], lut, hits, k00, offsets, n);
      } else {
        sum = SumTracedSamples({i, j, corner_rays, boards, gray_of, offsets, space}, n, sample_ray);
      }
      row[i] = sum / static_cast<float>(n * n);
    }
  }
  *boards_box = BoardsBox(boards, w, h);
  return true;
}

bool FrameRenderer::SampleRay(const Eigen::Matrix3d& a_inv, double u, double v,
                              Eigen::Vector3d* ray) const {
  Eigen::Vector2d xy = (a_inv * Eigen::Vector3d(u, v, 1.0)).head<2>();
  if (!IsPlaneFamily(intrinsics_.family)) return RayOfDistorted(intrinsics_, xy, ray);
  if (!UndistortNormalized(intrinsics_, Eigen::Vector2d(xy), &xy)) return false;
  *ray = LiftRay(RaySpace::kPlane, xy);
  return true;
}

CameraIntrinsics FinerCamera(const CameraIntrinsics& camera, int m) {
  CameraIntrinsics fine = camera;
  fine.fku_px *= m;
  fine.fkv_px *= m;
  fine.u0_px = m * (camera.u0_px + 0.5) - 0.5;
  fine.v0_px = m * (camera.v0_px + 0.5) - 0.5;
  return fine;
}

bool RenderFrame(const CameraIntrinsics& intrinsics, const std::vector<BoardView>& boards,
                 const RenderOptions& options, Rng* noise_rng, GrayImage* image, std::string* why) {
  const auto renderer = FrameRenderer::Create(intrinsics, options, why);
  return renderer != nullptr && renderer->Render(boards, noise_rng, image, why);
}

}  // namespace calibench
