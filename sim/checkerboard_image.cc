#include "sim/checkerboard_image.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/board_shader.h"
#include "sim/image_filters.h"
#include "sim/target.h"

namespace calibench {
namespace {

constexpr int kBackground = -1, kMargin = -2, kNoRay = -3;

// Where the rays of one camera meet the board: a square's key (>= 0), the margin or background.
class BoardHits {
 public:
  BoardHits(const CameraIntrinsics& camera, const Rigid3& cam_from_board,
            const CheckerboardPattern& pattern)
      : camera_(camera), pattern_(pattern) {
    a_inv_ = camera.Matrix().inverse();
    Eigen::Matrix3d plane;  // [r1 r2 t]: board (x, y, 1) -> point in the camera.
    plane << cam_from_board.rotation.col(0), cam_from_board.rotation.col(1),
        cam_from_board.translation;
    board_from_ray_ = plane.inverse();
  }

  // The key of what pixel point (u, v) sees.
  int KeyAt(double u, double v) const {
    const Eigen::Vector2d distorted = (a_inv_ * Eigen::Vector3d(u, v, 1)).head<2>();
    Eigen::Vector3d ray;
    if (!RayOfDistorted(camera_, distorted, &ray)) return kNoRay;
    const Eigen::Vector3d h = board_from_ray_ * ray;
    if (!(h.z() > 0)) return kBackground;  // The ray meets the plane behind the camera or never.
    const double s = pattern_.square_m;
    const double i = std::floor(h.x() / h.z() / s), j = std::floor(h.y() / h.z() / s);
    // Squares i in [-1, cols - 1], j in [-1, rows - 1]; the margin one square beyond.
    if (i < -2 || j < -2 || i > pattern_.cols || j > pattern_.rows) return kBackground;
    if (i < -1 || j < -1 || i > pattern_.cols - 1 || j > pattern_.rows - 1) return kMargin;
    return static_cast<int>((j + 1) * (pattern_.cols + 1) + (i + 1));
  }

  float Shade(int key, const CheckerboardImageOptions& o) const {
    if (key == kMargin) return static_cast<float>(o.white_gray);
    if (key < 0) return static_cast<float>(o.background_gray);
    const int i = key % (pattern_.cols + 1) - 1, j = key / (pattern_.cols + 1) - 1;
    return static_cast<float>((i + j) % 2 == 0 ? o.black_gray : o.white_gray);
  }

 private:
  const CameraIntrinsics& camera_;
  const CheckerboardPattern& pattern_;
  Eigen::Matrix3d a_inv_, board_from_ray_;
};

// The pixel box [x0, x1) x [y0, y1) holding the board and its margin: its outline projected at 64
// points a side, grown by 2 px; the whole image when a point of it does not project or the lens
// folds there (ProjectUnfolded), or the board holds an omnidirectional lens's backward axis.
PixelBox BoardBox(const CameraIntrinsics& camera, const Rigid3& cam_from_board,
                  const CheckerboardPattern& p, int width, int height) {
  const double s = p.square_m;
  const Eigen::Vector2d lo(-2 * s, -2 * s), hi((p.cols + 1) * s, (p.rows + 1) * s);
  const Eigen::Vector2d outline[5] = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}, lo};
  if (!render_internal::IsPlaneFamily(
          camera.family)) {  // The backward axis, -z, meets the board inside it?
    const Eigen::Vector3d normal = cam_from_board.rotation.col(2);
    const Eigen::Vector3d backward(0, 0, -1);
    const double along = normal.dot(cam_from_board.translation) / normal.dot(backward);
    if (along > 0) {
      const Eigen::Vector3d b =
          cam_from_board.rotation.transpose() * (along * backward - cam_from_board.translation);
      if (b.x() > lo.x() && b.x() < hi.x() && b.y() > lo.y() && b.y() < hi.y()) {
        return {0, width, 0, height};
      }
    }
  }
  Eigen::Vector2d min(1e300, 1e300), max(-1e300, -1e300);
  constexpr int kPerSide = 64;
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < kPerSide; ++k) {
      const Eigen::Vector2d b = outline[side] + (outline[side + 1] - outline[side]) * k / kPerSide;
      Eigen::Vector2d pixel;
      if (!render_internal::ProjectUnfolded(
              camera, cam_from_board * Eigen::Vector3d(b.x(), b.y(), 0), &pixel)) {
        return {0, width, 0, height};
      }
      min = min.cwiseMin(pixel);
      max = max.cwiseMax(pixel);
    }
  }
  auto clamp = [](double x, int n) { return static_cast<int>(std::clamp(x, 0.0, double(n))); };
  return {clamp(std::floor(min.x() - 2), width), clamp(std::ceil(max.x() + 3), width),
          clamp(std::floor(min.y() - 2), height), clamp(std::ceil(max.y() + 3), height)};
}

// The sharp, antialiased shade of every pixel of `camera`'s width x height image (header comment).
// *box: BoardBox, outside which the image is the background.
std::vector<float> ShadePixels(const CameraIntrinsics& camera, const Rigid3& cam_from_board,
                               const CheckerboardPattern& pattern,
                               const CheckerboardImageOptions& o, int width, int height,
                               PixelBox* box_out) {
  std::vector<float> values(static_cast<size_t>(width) * height,
                            static_cast<float>(o.background_gray));
  const PixelBox box = BoardBox(camera, cam_from_board, pattern, width, height);
  *box_out = box;
  if (box.x0 >= box.x1 || box.y0 >= box.y1) return values;
  const BoardHits hits(camera, cam_from_board, pattern);
  // Keys of the pixel corners of the box: corner (i, j) at (i - 0.5, j - 0.5).
  const int cw = box.x1 - box.x0 + 1, ch = box.y1 - box.y0 + 1;
  std::vector<int> corner_keys(static_cast<size_t>(cw) * ch);
  for (int j = 0; j < ch; ++j) {
    for (int i = 0; i < cw; ++i) {
      corner_keys[static_cast<size_t>(j) * cw + i] = hits.KeyAt(box.x0 + i - 0.5, box.y0 + j - 0.5);
    }
  }
  const int n = o.supersample;
  for (int y = box.y0; y < box.y1; ++y) {
    for (int x = box.x0; x < box.x1; ++x) {
      const size_t c = static_cast<size_t>(y - box.y0) * cw + (x - box.x0);
      const int key = corner_keys[c];
      float& value = values[static_cast<size_t>(y) * width + x];
      if (key == corner_keys[c + 1] && key == corner_keys[c + cw] &&
          key == corner_keys[c + cw + 1]) {
        value = hits.Shade(key, o);
        continue;
      }
      const float sum = render_internal::SumSamples(n, [&](int a, int b) {
        const Eigen::Vector2d offset = render_internal::SampleOffset(a, b, n);
        return hits.Shade(hits.KeyAt(x - 0.5 + offset.x(), y - 0.5 + offset.y()), o);
      });
      value = sum / static_cast<float>(n * n);
    }
  }
  return values;
}

}  // namespace

bool CheckerboardPattern::Check(std::string* why) const {
  if (cols >= 2 && rows >= 2 && cols <= kMaxCornersPerSide && rows <= kMaxCornersPerSide &&
      square_m > 0 && std::isfinite(square_m)) {
    return true;
  }
  if (why) {
    *why = "a checkerboard needs 2.." + std::to_string(kMaxCornersPerSide) +
           " inner corners a side and a positive, finite square";
  }
  return false;
}

bool CheckerboardImageOptions::Check(std::string* why) const {
  auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (width < 8 || height < 8 || width > kMaxRenderSide || height > kMaxRenderSide) {
    return fail("width and height must be 8.." + std::to_string(kMaxRenderSide) + " px");
  }
  if (supersample < 1 || supersample > 64) return fail("supersample must be 1..64");
  if (!(blur_sigma_px >= 0) || blur_sigma_px > 20) return fail("blur_sigma_px must be 0..20");
  if (!(noise_sigma_gray >= 0) || noise_sigma_gray > 100) {
    return fail("noise_sigma_gray must be 0..100");
  }
  for (const double gray : {background_gray, black_gray, white_gray}) {
    if (!(gray >= 0 && gray <= 255)) return fail("gray levels must be 0..255");
  }
  return true;
}

bool RenderCheckerboard(const CameraIntrinsics& camera, const Rigid3& cam_from_board,
                        const CheckerboardPattern& pattern, const CheckerboardImageOptions& options,
                        Rng* noise_rng, GrayImage* image, std::string* why) {
  *image = GrayImage();
  if (!options.Check(why)) return false;
  if (options.noise_sigma_gray > 0 && noise_rng == nullptr) {
    if (why) *why = "noise_sigma_gray > 0 needs a random generator";
    return false;
  }
  if (!pattern.Check(why)) return false;
  const int w = options.width, h = options.height;
  std::vector<float> values;
  PixelBox box{};
  if (options.blur_sigma_px > 0) {
    const int m = CapBlurGrid(AutoBlurGrid(options.blur_sigma_px), w, h);
    // Sub-pixels m times finer need m times fewer samples a side for the same resolution.
    CheckerboardImageOptions fine_options = options;
    fine_options.supersample = std::max(2, (options.supersample + m - 1) / m);
    const std::vector<float> fine = ShadePixels(FinerCamera(camera, m), cam_from_board, pattern,
                                                fine_options, w * m, h * m, &box);
    BlurNearBoardsAndSumBlocks(options.blur_sigma_px * m, w, h, m,
                               {box.x0, box.x1 - 1, box.y0, box.y1 - 1}, fine, &values);
  } else {
    values = ShadePixels(camera, cam_from_board, pattern, options, w, h, &box);
  }
  if (options.noise_sigma_gray > 0)
    AddImageNoise(options.noise_sigma_gray, w, h, noise_rng, &values);
  image->width = w;
  image->height = h;
  image->pixels.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    image->pixels[i] = static_cast<uint8_t>(std::clamp(std::lround(values[i]), 0L, 255L));
  }
  return true;
}

}  // namespace calibench
