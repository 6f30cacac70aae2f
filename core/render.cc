#include "core/render.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace calibench {
namespace {

constexpr int kOffBoard = -1;

// What a ray sees: -1 background, else 2 * board + (1 if white).
struct Scene {
  struct Board {
    const BoardView* view;
    Eigen::Matrix3d board_from_cam_rotation;
    Eigen::Vector3d normal;      // Board z axis in the camera frame.
    Eigen::Vector3d origin;      // Board origin in the camera frame.
    double cell, pitch, margin;  // Tag cell edge, tag pitch, white frame width.
  };
  std::vector<Board> boards;
  Eigen::Matrix3d a_inv;
  const CameraIntrinsics* intrinsics;
  bool distorted;
};

// Shade of board point (bx, by): 0 black, 1 white, kOffBoard outside the board.
int ShadeOnBoard(const Scene::Board& b, double bx, double by) {
  const AprilGrid& g = b.view->grid;
  const TagFamily& f = *b.view->family;
  const double extent_x = g.tag_cols * b.pitch - (b.pitch - g.tag_size_m);
  const double extent_y = g.tag_rows * b.pitch - (b.pitch - g.tag_size_m);
  if (bx < -b.margin || by < -b.margin || bx > extent_x + b.margin || by > extent_y + b.margin) {
    return kOffBoard;
  }
  const int start = f.border_start();
  // The tag whose full bitmap (reference square plus border_start cells around) may hold the point.
  const int c = static_cast<int>(std::floor((bx + start * b.cell) / b.pitch));
  const int r = static_cast<int>(std::floor((by + start * b.cell) / b.pitch));
  if (c < 0 || r < 0 || c >= g.tag_cols || r >= g.tag_rows) return 1;
  const double lx = bx - c * b.pitch, ly = by - r * b.pitch;
  const int col = static_cast<int>(std::floor(lx / b.cell)) + start;
  const int row_from_bottom = static_cast<int>(std::floor(ly / b.cell)) + start;
  const int w = f.total_width();
  if (col < 0 || row_from_bottom < 0 || col >= w || row_from_bottom >= w) return 1;
  return f.IsWhite(g.first_id + r * g.tag_cols + c, col, w - 1 - row_from_bottom) ? 1 : 0;
}

int Trace(const Scene& scene, double u, double v) {
  Eigen::Vector2d xy = (scene.a_inv * Eigen::Vector3d(u, v, 1.0)).head<2>();
  if (scene.distorted) {
    Eigen::Vector2d undistorted;
    if (!UndistortNormalized(*scene.intrinsics, xy, &undistorted)) return kOffBoard;
    xy = undistorted;
  }
  const Eigen::Vector3d ray(xy.x(), xy.y(), 1.0);
  double nearest = std::numeric_limits<double>::infinity();
  int hit = kOffBoard;
  for (size_t i = 0; i < scene.boards.size(); ++i) {
    const Scene::Board& b = scene.boards[i];
    const double denom = b.normal.dot(ray);
    if (std::abs(denom) < 1e-12) continue;
    const double s = b.normal.dot(b.origin) / denom;
    if (!(s > 0) || s >= nearest) continue;
    const Eigen::Vector3d in_board = b.board_from_cam_rotation * (s * ray - b.origin);
    const int shade = ShadeOnBoard(b, in_board.x(), in_board.y());
    if (shade == kOffBoard) continue;
    nearest = s;
    hit = 2 * static_cast<int>(i) + shade;
  }
  return hit;
}

void GaussianBlur(double sigma, int width, int height, std::vector<double>* image) {
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> kernel(2 * radius + 1);
  double sum = 0;
  for (int k = -radius; k <= radius; ++k)
    sum += kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  for (double& k : kernel) k /= sum;
  std::vector<double> tmp(image->size());
  auto clamp_index = [](int i, int n) { return std::clamp(i, 0, n - 1); };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double acc = 0;
      for (int k = -radius; k <= radius; ++k)
        acc += kernel[k + radius] * (*image)[y * width + clamp_index(x + k, width)];
      tmp[y * width + x] = acc;
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double acc = 0;
      for (int k = -radius; k <= radius; ++k)
        acc += kernel[k + radius] * tmp[clamp_index(y + k, height) * width + x];
      (*image)[y * width + x] = acc;
    }
  }
}

}  // namespace

bool RenderOptions::Check(std::string* why) const {
  std::string msg;
  if (width < 1 || height < 1) msg = "image size must be positive";
  if (supersample < 1 || supersample > 64) msg = "supersample must lie in [1, 64]";
  if (!(blur_sigma_px >= 0)) msg = "blur_sigma_px must be >= 0";
  if (!(noise_sigma_gray >= 0)) msg = "noise_sigma_gray must be >= 0";
  for (double g : {background_gray, black_gray, white_gray}) {
    if (!(g >= 0 && g <= 255)) msg = "gray levels must lie in [0, 255]";
  }
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

bool UndistortNormalized(const CameraIntrinsics& k, const Eigen::Vector2d& distorted,
                         Eigen::Vector2d* undistorted) {
  Eigen::Vector2d p = distorted;
  for (int it = 0; it < 100; ++it) {
    const double x = p.x(), y = p.y(), r2 = x * x + y * y;
    const double d = 1.0 + r2 * (k.k1 + r2 * (k.k2 + r2 * k.k3));
    const double dx = 2 * k.p1 * x * y + k.p2 * (r2 + 2 * x * x);
    const double dy = k.p1 * (r2 + 2 * y * y) + 2 * k.p2 * x * y;
    const Eigen::Vector2d next((distorted.x() - dx) / d, (distorted.y() - dy) / d);
    if (!next.allFinite() || d <= 0) return false;
    const double change = (next - p).norm();
    p = next;
    if (change < 1e-12) {
      *undistorted = p;
      return true;
    }
  }
  return false;
}

bool RenderFrame(const CameraIntrinsics& intrinsics, const std::vector<BoardView>& boards,
                 const RenderOptions& o, Rng* noise_rng, GrayImage* image, std::string* why) {
  if (!o.Check(why) || !intrinsics.Check(why)) return false;
  if (o.noise_sigma_gray > 0 && noise_rng == nullptr) {
    if (why) *why = "noise_sigma_gray > 0 needs a random generator";
    return false;
  }
  Scene scene;
  scene.a_inv = intrinsics.Matrix().inverse();
  scene.intrinsics = &intrinsics;
  scene.distorted = intrinsics.k1 != 0 || intrinsics.k2 != 0 || intrinsics.k3 != 0 ||
                    intrinsics.p1 != 0 || intrinsics.p2 != 0;
  for (const BoardView& view : boards) {
    if (!view.family || view.family->name() != view.grid.family) {
      if (why) *why = "board family '" + view.grid.family + "' has no matching TagFamily";
      return false;
    }
    if (view.grid.first_id + view.grid.NumTags() > view.family->num_codes()) {
      if (why)
        *why = view.grid.family + " has only " + std::to_string(view.family->num_codes()) +
               " codes, the grid needs ids up to " +
               std::to_string(view.grid.first_id + view.grid.NumTags() - 1);
      return false;
    }
    Scene::Board b;
    b.view = &view;
    b.board_from_cam_rotation = view.cam_from_board.rotation.transpose();
    b.normal = view.cam_from_board.rotation.col(2);
    b.origin = view.cam_from_board.translation;
    b.cell = view.grid.tag_size_m / view.family->width_at_border();
    b.pitch = view.grid.Pitch();
    b.margin = b.pitch - view.grid.tag_size_m;
    scene.boards.push_back(b);
  }
  const int w = o.width, h = o.height, n = o.supersample;
  auto gray = [&](int shade) {
    return shade == kOffBoard ? o.background_gray : (shade % 2 ? o.white_gray : o.black_gray);
  };
  // Shades at pixel corners (w + 1) x (h + 1): corner (i, j) is at (i - 0.5, j - 0.5).
  std::vector<int> corners(static_cast<size_t>(w + 1) * (h + 1));
  for (int j = 0; j <= h; ++j) {
    for (int i = 0; i <= w; ++i) corners[j * (w + 1) + i] = Trace(scene, i - 0.5, j - 0.5);
  }
  std::vector<double> values(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const int c00 = corners[j * (w + 1) + i], c10 = corners[j * (w + 1) + i + 1];
      const int c01 = corners[(j + 1) * (w + 1) + i], c11 = corners[(j + 1) * (w + 1) + i + 1];
      if (c00 == c10 && c00 == c01 && c00 == c11) {
        values[j * w + i] = gray(c00);
        continue;
      }
      double sum = 0;
      for (int b = 0; b < n; ++b) {
        for (int a = 0; a < n; ++a) {
          sum += gray(Trace(scene, i - 0.5 + (a + 0.5) / n, j - 0.5 + (b + 0.5) / n));
        }
      }
      values[j * w + i] = sum / (n * n);
    }
  }
  if (o.blur_sigma_px > 0) GaussianBlur(o.blur_sigma_px, w, h, &values);
  image->width = w;
  image->height = h;
  image->pixels.resize(values.size());
  for (size_t k = 0; k < values.size(); ++k) {
    double v = values[k];
    if (o.noise_sigma_gray > 0) v += o.noise_sigma_gray * noise_rng->Normal();
    image->pixels[k] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return true;
}

}  // namespace calibench
