#include "sim/render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "sim/board_shader.h"
#include "sim/image_filters.h"

namespace calibench {
namespace {

using render_internal::BoardShader;
using render_internal::IsPlaneFamily;
using render_internal::kOffBoard;
using render_internal::LiftRay;
using render_internal::RaySpace;
using render_internal::RaySpaceOf;
using render_internal::SampleOffset;
using render_internal::Stereographic;
using render_internal::SumSamples;
using render_internal::TraceBoards;

constexpr int kMaxBlurGrid = 8;  // Sub-pixels per side of the automatic blur grid.
constexpr double kMaxFinePixels = 16e6;

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

// The weights of 4-point Lagrange interpolation at t in [0, 1) between nodes -1, 0, 1, 2.
std::array<double, 4> CubicWeights(double t) {
  return {-t * (t - 1) * (t - 2) / 6, (t + 1) * (t - 1) * (t - 2) / 2, -(t + 1) * t * (t - 2) / 2,
          (t + 1) * t * (t - 1) / 6};
}

// The corner rays of a grid m times finer, interpolated between the pixel corners' by the
// tensor-product cubic through the 4 x 4 nearest (exact for cubics: its error is of fourth order
// in the pixel's size over the lens's scale, < 1e-6 px in a 160 deg fisheye's periphery where
// bilinear interpolation moved edges inwards by 1e-3 to 7e-3 px), and computed exactly (`finer`:
// the finer grid's camera) where the 4 x 4 corners are not all in the image or not all valid. m^2
// times fewer inversions of the lens than a table built for the finer grid.
std::vector<Eigen::Vector2d> FinerRayTable(const std::vector<Eigen::Vector2d>& coarse,
                                           const CameraIntrinsics& finer, int w, int h, int m) {
  const Eigen::Matrix3d a_inv = finer.Matrix().inverse();
  const size_t stride = static_cast<size_t>(w) * m + 1;
  std::vector<Eigen::Vector2d> table(stride * (static_cast<size_t>(h) * m + 1));
  std::vector<std::array<double, 4>> weights(m);
  for (int f = 0; f < m; ++f) weights[f] = CubicWeights(static_cast<double>(f) / m);
  for (int jj = 0; jj <= h * m; ++jj) {
    const int j = std::min(jj / m, h - 1);
    const int fb = jj - j * m;
    for (int ii = 0; ii <= w * m; ++ii) {
      const int i = std::min(ii / m, w - 1);
      const int fa = ii - i * m;
      Eigen::Vector2d ray(std::numeric_limits<double>::quiet_NaN(), 0);
      if (fa == 0 && fb == 0) {
        ray = coarse[static_cast<size_t>(j) * (w + 1) + i];  // A pixel corner: its own ray.
      } else if (i >= 1 && j >= 1 && i + 2 <= w && j + 2 <= h) {
        ray.setZero();
        for (int b = 0; b < 4; ++b) {
          const Eigen::Vector2d* row = &coarse[static_cast<size_t>(j - 1 + b) * (w + 1) + i - 1];
          const Eigen::Vector2d across = weights[fa][0] * row[0] + weights[fa][1] * row[1] +
                                         weights[fa][2] * row[2] + weights[fa][3] * row[3];
          ray += weights[fb][b] * across;
        }
      }
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
    const int m = CapBlurGrid(
        options.blur_grid > 0 ? options.blur_grid : AutoBlurGrid(options.blur_sigma_px), w, h);
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
  std::vector<uint32_t>& cell;             // BoardShader::ShadeAndCell's, where hit >= 0.
  size_t stride;
};

// Whether four corners on the same board and shade may hold a pixel of another shade between
// them: a corner of the pattern (a tag's, a cell's) pokes in when both a column and a row line
// cross the pixel. One axis's lines alone cross it from side to side and change the shade there
// only for cells thinner than a pixel (the renderer assumes features larger than a pixel).
bool MayHoldAPatternCorner(const CornerHits& hits, size_t k00) {
  const size_t k01 = k00 + hits.stride;
  const uint32_t a = hits.cell[k00];
  const uint32_t differ =
      (a ^ hits.cell[k00 + 1]) | (a ^ hits.cell[k01]) | (a ^ hits.cell[k01 + 1]);
  return (differ >> 16) != 0 && (differ & 0xFFFF) != 0;
}

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
        hits->hit[k] = static_cast<int16_t>(2 * b + board.ShadeAndCell(bx, by, &hits->cell[k]));
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

// The mean gray of a pixel that sees one board: its footprint there is the quadrilateral of its
// corners' board points (straight-sided: the rays inside a pixel are bilinear in the pixel, the
// board a homography of them), each cell's share of the pixel exact (BoardShader::
// MeanOverFootprint; through a lens to second order in the pixel's size). Cells far below a
// pixel: the n x n samples' mean, their board points interpolated between the corners'.
// lut: off-board, black, white.
float MeanOnOneBoard(const BoardShader& shader, const std::array<float, 3>& lut,
                     const CornerHits& hits, size_t k00,
                     const std::vector<Eigen::Vector2d>& offsets, int n) {
  const size_t k01 = k00 + hits.stride;
  const std::array<Eigen::Vector2d, 4> quad = {
      hits.in_board[k00].cast<double>(), hits.in_board[k00 + 1].cast<double>(),
      hits.in_board[k01 + 1].cast<double>(), hits.in_board[k01].cast<double>()};
  float mean = 0;
  if (shader.MeanOverFootprint(quad, lut, &mean)) return mean;
  // b(fa, fb) = p + fa u + fb v + fa fb q over the pixel, from its corners' board points.
  const Eigen::Vector2d& p = quad[0];
  const Eigen::Vector2d u = quad[1] - p, v = quad[3] - p;
  const Eigen::Vector2d q = quad[2] - p - u - v;
  const float sum = SumSamples(n, [&](int a, int b) {
    const Eigen::Vector2d& f = offsets[b * n + a];
    const Eigen::Vector2d point = p + f.x() * u + f.y() * v + f.x() * f.y() * q;
    return lut[shader.Shade(point.x(), point.y()) + 1];
  });
  return sum / static_cast<float>(n * n);
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
  thread_local std::vector<uint32_t> corner_cells;
  const size_t num_corners = static_cast<size_t>(w + 1) * (h + 1);
  corners.assign(num_corners, kOffBoard);
  corner_in_board.resize(num_corners);
  corner_cells.resize(num_corners);
  const Eigen::Matrix3d a_inv = intrinsics_.Matrix().inverse();
  const CornerRays corner_rays{corner_rays_, a_inv, stride};
  CornerHits hits{corners, corner_in_board, corner_cells, stride};
  const RaySpace space = RaySpaceOf(intrinsics_.family);
  TraceCorners(boards, corner_rays, space, h, &hits);
  // Pass 2, pixels: one shade if the four corners agree and no pattern corner pokes in between
  // them (MayHoldAPatternCorner); else, when the pixel sees one board only,
  // the exact area shares of its footprint there (MeanOnOneBoard); else n x n traced samples.
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
      const size_t k00 = j * stride + i;
      if (c00 == top[i + 1] && c00 == bottom[i] && c00 == bottom[i + 1] &&
          (c00 == kOffBoard || !MayHoldAPatternCorner(hits, k00))) {
        row[i] = gray_of[c00 + 1];
        continue;
      }
      if (SeesOneBoard(boards, hits, k00, i, j)) {
        const int board = c00 / 2;
        const std::array<float, 3> lut = {gray_of[kOffBoard + 1], gray_of[2 * board + 1],
                                          gray_of[2 * board + 2]};
        row[i] = MeanOnOneBoard(boards[board], lut, hits, k00, offsets, n);
        continue;
      }
      const float sum =
          SumTracedSamples({i, j, corner_rays, boards, gray_of, offsets, space}, n, sample_ray);
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

int AutoBlurGrid(double blur_sigma_px) {
  return std::min(kMaxBlurGrid, static_cast<int>(std::ceil(3 / blur_sigma_px)));
}

int CapBlurGrid(int m, int width, int height) {
  while (m > 1 && static_cast<double>(width) * m * height * m > kMaxFinePixels) --m;
  return m;
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
