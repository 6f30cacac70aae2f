// The blur's finer grid through a fisheye's periphery (sim/render.h: its corner rays interpolated
// between the pixel corners' by a cubic): a blurred board rendered by FrameRenderer against one
// rendered by brute force (8 x 8 point samples a pixel, each through the exact lens, the blur on
// that grid, summed to pixels), compared by where their edges lie along the radial direction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/board_shader.h"
#include "sim/render.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kSide = 800;
constexpr double kBlurPx = 0.8;

// A 160 deg equidistant (Kannala-Brandt) lens whose half field lands 380 px from the centre (as
// tests/bench/calibrate_wide_rendered_test.cc's pinhole-equi truth).
CameraIntrinsics Fisheye160() {
  CameraIntrinsics k;
  k.family = LensFamily::kEquidistant;
  k.k1 = 0.02, k.k2 = -0.01, k.k3 = 0.003, k.k4 = -5e-4;
  const double f = FocalLengthPuttingRayAt(k, 80, 380);
  k.fku_px = f, k.fkv_px = 1.002 * f, k.u0_px = 401.7, k.v0_px = 397.6;
  return k;
}

struct Box {
  int x0, y0, x1, y1;  // Pixels [x0, x1) x [y0, y1).
};

// The brute-force image over `box` (float gray levels, row-major): m x m point samples a pixel
// through UnprojectToRay, blurred by kBlurPx on that grid, summed to pixels. The blur needs the
// samples around the box: they are traced over the box grown by 4 px.
std::vector<double> BruteForce(const CameraIntrinsics& k, const BoardView& view, const Box& box,
                               int m, const RenderOptions& ro) {
  render_internal::BoardShader shader;
  std::string why;
  EXPECT_TRUE(shader.Init(view, Eigen::Matrix3d::Identity(), &why)) << why;
  constexpr int kMarginPx = 4;
  const int w = (box.x1 - box.x0 + 2 * kMarginPx) * m, h = (box.y1 - box.y0 + 2 * kMarginPx) * m;
  const double gray[3] = {ro.background_gray, ro.black_gray, ro.white_gray};
  std::vector<double> fine(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector2d pixel(box.x0 - kMarginPx + (x + 0.5) / m - 0.5,
                                  box.y0 - kMarginPx + (y + 0.5) / m - 0.5);
      Eigen::Vector3d ray;
      double value = gray[0];
      double bx, by, depth;
      if (UnprojectToRay(k, pixel, &ray) && shader.ToBoard(ray, &bx, &by, &depth)) {
        value = gray[shader.Shade(bx, by) + 1];
      }
      fine[static_cast<size_t>(y) * w + x] = value;
    }
  }
  const double s = kBlurPx * m;
  const int r = static_cast<int>(std::ceil(4 * s));
  std::vector<double> kernel(2 * r + 1);
  double sum = 0;
  for (int i = -r; i <= r; ++i) sum += kernel[i + r] = std::exp(-0.5 * i * i / (s * s));
  for (double& weight : kernel) weight /= sum;
  std::vector<double> rows(fine.size()), blurred(fine.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double a = 0;
      for (int i = -r; i <= r; ++i) a += kernel[i + r] * fine[y * w + std::clamp(x + i, 0, w - 1)];
      rows[static_cast<size_t>(y) * w + x] = a;
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double a = 0;
      for (int i = -r; i <= r; ++i) a += kernel[i + r] * rows[std::clamp(y + i, 0, h - 1) * w + x];
      blurred[static_cast<size_t>(y) * w + x] = a;
    }
  }
  std::vector<double> out;
  for (int y = box.y0; y < box.y1; ++y) {
    for (int x = box.x0; x < box.x1; ++x) {
      double a = 0;
      for (int j = 0; j < m; ++j) {
        for (int i = 0; i < m; ++i) {
          a += blurred[static_cast<size_t>((y - box.y0 + kMarginPx) * m + j) * w +
                       (x - box.x0 + kMarginPx) * m + i];
        }
      }
      out.push_back(a / (m * m));
    }
  }
  return out;
}

// A board 62-78 deg off the axis: FrameRenderer's edges lie where the exact lens puts them. The
// shift along the radial direction (outward from the principal point) that best explains the
// difference of the two images, delta = -sum dI g / sum g^2 with g the reference's radial
// gradient, is measured at -1.1e-4 px (what remains: each sub-pixel's footprint is straight-sided,
// second order in its size, and the 8-bit rounding); with the finer grid's rays interpolated
// bilinearly (the earlier renderer) it was -1.7e-3 px. kShiftTolerancePx is 2.7x the former and
// under a fifth of the latter.
constexpr double kShiftTolerancePx = 3e-4;

TEST(RenderFineGrid, EdgesThroughAFisheyesPeripheryLieWhereTheExactLensPutsThem) {
  const CameraIntrinsics k = Fisheye160();
  AprilGrid grid;
  grid.tag_rows = grid.tag_cols = 2;
  grid.tag_size_m = 0.05;
  const auto family = TagFamily::Create(grid.family, grid.black_tag_border, nullptr);
  ASSERT_TRUE(family);
  const double extent = grid.Pitch() + grid.tag_size_m;
  const Eigen::Vector3d centre(extent / 2, extent / 2, 0);
  // Facing the camera from 70 deg off the axis, 0.4 m away (62-78 deg).
  const Eigen::Vector3d direction(std::sin(70 * kDeg), 0, std::cos(70 * kDeg));
  Rigid3 cam_from_board;
  const Eigen::Vector3d z = -direction;  // The board's normal towards the camera.
  const Eigen::Vector3d board_x = Eigen::Vector3d::UnitY().cross(z).normalized();
  cam_from_board.rotation << board_x, z.cross(board_x), z;
  cam_from_board.translation = 0.4 * direction - cam_from_board.rotation * centre;
  const BoardView view{grid, family, cam_from_board};

  RenderOptions ro;
  ro.width = ro.height = kSide;
  ro.blur_sigma_px = kBlurPx;
  ro.blur_grid = 2;
  std::string why;
  const auto renderer = FrameRenderer::Create(k, ro, &why);
  ASSERT_TRUE(renderer) << why;
  GrayImage image;
  Rng rng(1);
  ASSERT_TRUE(renderer->Render({view}, &rng, &image, &why)) << why;

  // The board's pixels, by its corners' projections.
  Box box{kSide, kSide, 0, 0};
  for (double bx : {-0.02, extent + 0.02}) {
    for (double by : {-0.02, extent + 0.02}) {
      Eigen::Vector2d p;
      ASSERT_TRUE(ProjectPoint(k, cam_from_board * Eigen::Vector3d(bx, by, 0), &p));
      box.x0 = std::min(box.x0, static_cast<int>(p.x()) - 2);
      box.y0 = std::min(box.y0, static_cast<int>(p.y()) - 2);
      box.x1 = std::max(box.x1, static_cast<int>(p.x()) + 3);
      box.y1 = std::max(box.y1, static_cast<int>(p.y()) + 3);
    }
  }
  ASSERT_TRUE(box.x0 > 8 && box.y0 > 8 && box.x1 < kSide - 8 && box.y1 < kSide - 8);
  const std::vector<double> reference = BruteForce(k, view, box, 8, ro);
  const int w = box.x1 - box.x0;
  double num = 0, den = 0;
  for (int y = box.y0 + 1; y < box.y1 - 1; ++y) {
    for (int x = box.x0 + 1; x < box.x1 - 1; ++x) {
      const int i = (y - box.y0) * w + (x - box.x0);
      const Eigen::Vector2d gradient(0.5 * (reference[i + 1] - reference[i - 1]),
                                     0.5 * (reference[i + w] - reference[i - w]));
      const Eigen::Vector2d outward =
          (Eigen::Vector2d(x, y) - Eigen::Vector2d(k.u0_px, k.v0_px)).normalized();
      const double g = gradient.dot(outward);
      num += (image.at(x, y) - reference[i]) * g;
      den += g * g;
    }
  }
  ASSERT_GT(den, 0);
  const double shift_px = -num / den;
  EXPECT_LT(std::abs(shift_px), kShiftTolerancePx) << "edges shifted " << shift_px << " px";
}

}  // namespace
}  // namespace calibench
