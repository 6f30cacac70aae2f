// The renderer (sim/render.h): tag bitmaps, where edges land and the pixels' exact cell areas,
// noise and blur; through every lens family: render_lenses_test.cc.
#include "sim/render.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/synthetic.h"

namespace calibench {
namespace {

// Fronto-parallel board 1 m in front of the camera: board x -> image u, board y -> image -v.
BoardView FrontoParallel(double tx, double ty) {
  BoardView b;
  b.grid.tag_rows = 2;
  b.grid.tag_cols = 2;
  b.grid.tag_size_m = 0.2;
  b.family = TagFamily::Create("tag36h11", nullptr);
  b.cam_from_board.rotation = Eigen::Vector3d(1, -1, -1).asDiagonal();
  b.cam_from_board.translation = Eigen::Vector3d(tx, ty, 1.0);
  return b;
}

// A sharp, noise-free 640 x 480 frame of one board, black 0 / white 255, with n x n samples where
// the renderer samples.
bool RenderBlackOnWhite(const CameraIntrinsics& k, const BoardView& board, int supersample,
                        GrayImage* image, std::string* why) {
  RenderOptions o;
  o.supersample = supersample;
  o.black_gray = 0;
  o.white_gray = 255;
  return RenderFrame(k, {board}, o, nullptr, image, why);
}

TEST(TagFamily, BitmapsComeFromTheLibrary) {
  std::string why;
  const auto f = TagFamily::Create("tag36h11", &why);
  ASSERT_NE(f, nullptr) << why;
  EXPECT_EQ(f->num_codes(), 587);
  EXPECT_EQ(f->total_width(), 10);
  EXPECT_EQ(f->width_at_border(), 8);
  for (int k = 0; k < 10; ++k) {
    EXPECT_TRUE(f->IsWhite(0, k, 0));                       // Outer white ring.
    EXPECT_FALSE(f->IsWhite(0, k, 1) && k >= 1 && k <= 8);  // Black border row.
  }
  EXPECT_EQ(TagFamily::Create("tag99h1", &why), nullptr);
  EXPECT_NE(why.find("tag99h1"), std::string::npos);
}

// Kalibr's layout (kalibr_create_target_pdf: bit = tagSize / (6 + 2 * 2)): the 1-bit family grown
// by one black ring. Every cell of the 12 x 12 bitmap: ring 0 white, rings 1-2 black, and the
// 6 x 6 data block equal to the 1-bit bitmap's, moved by one cell.
TEST(TagFamily, TwoBitBorderIsTheLibrarysTagGrownByABlackRing) {
  std::string why;
  const auto one = TagFamily::Create("tag36h11", 1, &why);
  const auto two = TagFamily::Create("tag36h11", 2, &why);
  ASSERT_NE(two, nullptr) << why;
  EXPECT_EQ(two->border_bits(), 2);
  EXPECT_EQ(two->total_width(), 12);
  EXPECT_EQ(two->width_at_border(), 10);
  EXPECT_EQ(two->border_start(), 1);
  EXPECT_EQ(two->num_codes(), one->num_codes());
  for (int id : {0, 1, 17, 586}) {
    for (int row = 0; row < 12; ++row) {
      for (int col = 0; col < 12; ++col) {
        const int ring = std::min({row, col, 11 - row, 11 - col});
        const bool expected = ring == 0   ? true
                              : ring <= 2 ? false
                                          : one->IsWhite(id, col - 1, row - 1);
        EXPECT_EQ(two->IsWhite(id, col, row), expected) << id << " " << col << " " << row;
      }
    }
  }
  EXPECT_EQ(TagFamily::Create("tag36h11", 3, &why), nullptr);
  EXPECT_NE(why.find("must be 1 (AprilTag 3) or 2"), std::string::npos) << why;
  EXPECT_EQ(TagFamily::Create("tagCircle21h7", 2, &why), nullptr);
  EXPECT_NE(why.find("reversed"), std::string::npos) << why;
}

// A board whose family has another border width than the grid's is refused, not drawn wrong.
TEST(Render, FamilyMustMatchTheGridsBorder) {
  BoardView b = FrontoParallel(-0.2, -0.2);
  b.grid.black_tag_border = 2;  // The family is the 1-bit one.
  GrayImage img;
  std::string why;
  EXPECT_FALSE(
      RenderFrame({500, 500, 90, 319.5, 239.5}, {b}, RenderOptions(), nullptr, &img, &why));
  EXPECT_NE(why.find("2-bit border has no matching TagFamily"), std::string::npos) << why;
}

// The pixel-centre convention: an edge placed exactly between two sub-samples of pixel 100
// (u = 99.5 + 45/64) is read back from the pixel's area fraction to 0.01 px (quantisation to
// 8 bits with black 0 / white 255 leaves 0.002 px).
TEST(Render, EdgeLandsWhereTheCameraModelPutsIt) {
  const CameraIntrinsics k{500, 500, 90, 319.5, 239.5};
  const double edge_u = 99.5 + 45.0 / 64.0;
  // Tag 0's left edge is board x = 0: u = 500 * tx + 319.5.
  BoardView b = FrontoParallel((edge_u - 319.5) / 500, -0.1);
  GrayImage img;
  std::string why;
  ASSERT_TRUE(RenderBlackOnWhite(k, b, 64, &img, &why)) << why;
  // Row through the lower part of tag 0's black border (board y in (0, s/8)).
  // v = 239.5 + 500 * (-y - 0.1): board y = s/16 = 0.0125 m is v = 183.25.
  const int row = static_cast<int>(std::lround(239.5 + 500 * (-0.0125 - 0.1)));
  EXPECT_EQ(img.at(98, row), 255);  // White margin left of the tag.
  EXPECT_EQ(img.at(102, row), 0);   // Black border.
  const double black_fraction = 1.0 - img.at(100, row) / 255.0;
  const double estimated_edge = 100.5 - black_fraction;
  EXPECT_NEAR(estimated_edge, edge_u, 0.01);
}

// Area of the unit pixel square (i, j) (pixel-centre convention) inside a convex polygon given
// counter-clockwise or clockwise: the square clipped by each of the polygon's edge lines in turn.
double PixelAreaInside(int i, int j, const std::vector<Eigen::Vector2d>& polygon) {
  std::vector<Eigen::Vector2d> piece = {
      {i - 0.5, j - 0.5}, {i + 0.5, j - 0.5}, {i + 0.5, j + 0.5}, {i - 0.5, j + 0.5}};
  double orientation = 0;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& a = polygon[k];
    const Eigen::Vector2d& b = polygon[(k + 1) % polygon.size()];
    orientation += a.x() * b.y() - a.y() * b.x();
  }
  for (size_t e = 0; e < polygon.size() && !piece.empty(); ++e) {
    const Eigen::Vector2d& a = polygon[e];
    const Eigen::Vector2d d = polygon[(e + 1) % polygon.size()] - a;
    const auto side = [&](const Eigen::Vector2d& x) {  // > 0 inside.
      return (orientation > 0 ? 1 : -1) * (d.x() * (x.y() - a.y()) - d.y() * (x.x() - a.x()));
    };
    std::vector<Eigen::Vector2d> kept;
    for (size_t k = 0; k < piece.size(); ++k) {
      const Eigen::Vector2d& p = piece[k];
      const Eigen::Vector2d& q = piece[(k + 1) % piece.size()];
      const double sp = side(p), sq = side(q);
      if (sp >= 0) kept.push_back(p);
      if ((sp >= 0) != (sq >= 0)) kept.push_back(p + sp / (sp - sq) * (q - p));
    }
    piece = kept;
  }
  double area = 0;
  for (size_t k = 0; k < piece.size(); ++k) {
    const Eigen::Vector2d& p = piece[k];
    const Eigen::Vector2d& q = piece[(k + 1) % piece.size()];
    area += p.x() * q.y() - p.y() * q.x();
  }
  return std::abs(area) / 2;
}

// A pixel on one board holds the exact area share of every cell it overlaps, whatever the
// supersampling (supersample 1: one sample a pixel), black 0 / white 255. Two views of tag 0:
// seen at 40 deg of tilt and 20 deg of roll (13-20 px cells), and frontal on the pixel grid (its
// corner on a pixel corner, 3.75 px cells: every other cell line on a pixel boundary, lattice
// points on pixel corners). Every pixel of the tag's bitmap against the
// share of the pixel inside the images of its black cells, quadrilaterals (pinhole), computed in
// the image (pixels wholly inside the bitmap: other tags lie beyond it). Tolerance kTolGray: the
// 8-bit rounding (0.5 gray) and the float board points (< 0.01 gray); measured worst 0.500 gray.
// Mutations checked: board-area shares for pixel-area shares (no PixelFromBoard: the homography's
// change of scale across a pixel ignored) put pixels 0.63 gray off; 4 x 4 samples instead
// (MeanOverFootprint refused, supersample 4) 31 gray; without MayHoldAPatternCorner, a tag corner
// poking into a pixel whose four corners are white is lost (13 gray); shading one side of a single
// line at a footprint corner instead of its piece's centroid takes the cell beyond a pixel whose
// side lies on a cell line (frontal case, 191 gray).
TEST(Render, PixelsOnOneBoardHoldTheExactAreaOfEachCell) {
  constexpr double kTolGray = 0.51;
  const CameraIntrinsics k{500, 500, 90, 319.5, 239.5};
  BoardView tilted = FrontoParallel(0, 0);
  tilted.grid.tag_size_m = 0.16;
  tilted.cam_from_board.rotation = (Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(40 * M_PI / 180, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix() *
                                   tilted.cam_from_board.rotation;
  tilted.cam_from_board.translation = Eigen::Vector3d(-0.05, -0.04, 0.9);
  // Board (0, 0) at u = 319.5 + 500 (-0.35) = 144.5, v = 239.5 + 500 (-0.1) = 189.5.
  BoardView frontal = FrontoParallel(-0.35, -0.1);
  frontal.grid.tag_size_m = 0.06;
  for (const BoardView& b : {tilted, frontal}) {
    GrayImage img;
    std::string why;
    ASSERT_TRUE(RenderBlackOnWhite(k, b, 1, &img, &why)) << why;
    // The images of tag 0's black cells: cell (col, row) of the bitmap (row 0 at the top) spans
    // board x in [(col - start) c, (col - start + 1) c], y in [(w - 1 - row - start) c, ...].
    const TagFamily& f = *b.family;
    const double cell = b.grid.tag_size_m / f.width_at_border();
    const int start = f.border_start(), w = f.total_width();
    std::vector<std::vector<Eigen::Vector2d>> black_cells;
    std::vector<Eigen::Vector2d> bitmap;  // The whole bitmap, its white ring included.
    for (const Eigen::Vector3d& corner :
         {Eigen::Vector3d(-start, -start, 0), Eigen::Vector3d(w - start, -start, 0),
          Eigen::Vector3d(w - start, w - start, 0), Eigen::Vector3d(-start, w - start, 0)}) {
      Eigen::Vector2d pixel;
      ASSERT_TRUE(ProjectPoint(k, b.cam_from_board * (cell * corner), &pixel));
      bitmap.push_back(pixel);
    }
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e9), hi = -lo;
    for (int row = 0; row < w; ++row) {
      for (int col = 0; col < w; ++col) {
        if (f.IsWhite(b.grid.first_id, col, row)) continue;
        const double x0 = (col - start) * cell, y0 = (w - 1 - row - start) * cell;
        std::vector<Eigen::Vector2d> quad;
        for (const Eigen::Vector3d& corner :
             {Eigen::Vector3d(x0, y0, 0), Eigen::Vector3d(x0 + cell, y0, 0),
              Eigen::Vector3d(x0 + cell, y0 + cell, 0), Eigen::Vector3d(x0, y0 + cell, 0)}) {
          Eigen::Vector2d pixel;
          ASSERT_TRUE(ProjectPoint(k, b.cam_from_board * corner, &pixel));
          quad.push_back(pixel);
          lo = lo.cwiseMin(pixel), hi = hi.cwiseMax(pixel);
        }
        black_cells.push_back(quad);
      }
    }
    int mixed_pixels = 0;
    double worst = 0;
    for (int j = static_cast<int>(lo.y()) - 3; j <= static_cast<int>(hi.y()) + 3; ++j) {
      for (int i = static_cast<int>(lo.x()) - 3; i <= static_cast<int>(hi.x()) + 3; ++i) {
        if (PixelAreaInside(i, j, bitmap) < 1 - 1e-12) continue;  // Other tags may be near.
        double black = 0;
        for (const std::vector<Eigen::Vector2d>& quad : black_cells) {
          black += PixelAreaInside(i, j, quad);
        }
        const double error = img.at(i, j) - 255 * (1 - black);
        EXPECT_LE(std::abs(error), kTolGray) << "pixel " << i << ", " << j << ": black " << black;
        worst = std::max(worst, std::abs(error));
        mixed_pixels += black > 1e-3 && black < 1 - 1e-3;
      }
    }
    EXPECT_GT(mixed_pixels, 100);
    std::printf("%d pixels of mixed cells, worst %.3f gray\n", mixed_pixels, worst);
  }
}

TEST(Render, BackgroundNoiseAndBlurBehave) {
  const CameraIntrinsics k{500, 500, 90, 319.5, 239.5};
  RenderOptions o;
  o.noise_sigma_gray = 3.0;
  GrayImage img;
  std::string why;
  EXPECT_FALSE(RenderFrame(k, {FrontoParallel(0, 0)}, o, nullptr, &img, &why));  // Needs an Rng.
  Rng rng(1);
  o.background_gray = 100;
  ASSERT_TRUE(RenderFrame(k, {}, o, &rng, &img, &why)) << why;
  double sum = 0, sum_sq = 0;
  for (uint8_t p : img.pixels) sum += p, sum_sq += p * p;
  const double n = static_cast<double>(img.pixels.size());
  EXPECT_NEAR(sum / n, 100.0, 0.05);
  // Rounding adds 1/12 to the variance: sqrt(9 + 1/12) = 3.014.
  EXPECT_NEAR(std::sqrt(sum_sq / n - (sum / n) * (sum / n)), 3.014, 0.03);
  BoardView too_many = FrontoParallel(0, 0);
  too_many.grid.tag_rows = 30;
  too_many.grid.tag_cols = 30;  // 900 tags > 587 codes.
  EXPECT_FALSE(RenderFrame(k, {too_many}, RenderOptions(), nullptr, &img, &why));
  EXPECT_NE(why.find("587"), std::string::npos) << why;
  // A row of 6000 tagStandard52h13 tags (48714 codes): more than the renderer's 16-bit cell keys
  // number along a side (65535 / (bitmap width 10 + 1) - 2 = 5955).
  BoardView long_row = FrontoParallel(0, 0);
  long_row.grid.family = "tagStandard52h13";
  long_row.family = TagFamily::Create("tagStandard52h13", nullptr);
  long_row.grid.tag_rows = 1;
  long_row.grid.tag_cols = 6000;
  ASSERT_NE(long_row.family, nullptr);
  EXPECT_FALSE(RenderFrame(k, {long_row}, RenderOptions(), nullptr, &img, &why));
  EXPECT_NE(why.find("at most 5955 tagStandard52h13 tags along a side of a grid (given 6000)"),
            std::string::npos)
      << why;
}

// The noise table (image_filters.h AddImageNoise): a frame's noise is uncorrelated between
// neighbours in a row, between rows and between the two halves of a row block boundary (|rho| below
// kRhoBound = 5 / sqrt(n), 5 sigma of a zero correlation over n pairs); a seed gives one frame;
// two seeds give frames whose noise is uncorrelated.
TEST(Render, NoiseIsUncorrelatedWithinAndAcrossFrames) {
  const CameraIntrinsics k{500, 500, 90, 319.5, 239.5};
  RenderOptions o;
  o.noise_sigma_gray = 8.0;
  o.background_gray = 128;
  auto frame = [&](uint64_t seed) {
    Rng rng(seed);
    GrayImage img;
    EXPECT_TRUE(RenderFrame(k, {}, o, &rng, &img, nullptr));
    std::vector<double> v(img.pixels.begin(), img.pixels.end());
    for (double& x : v) x -= 128;
    return v;
  };
  const std::vector<double> a = frame(1), b = frame(2);
  EXPECT_EQ(a, frame(1));
  const int w = 640, h = 480;
  auto rho = [](const std::vector<double>& x, const std::vector<double>& y) {
    double xy = 0, xx = 0, yy = 0;
    for (size_t i = 0; i < x.size(); ++i) xy += x[i] * y[i], xx += x[i] * x[i], yy += y[i] * y[i];
    return xy / std::sqrt(xx * yy);
  };
  std::vector<double> left, right, up, down, across_a, across_b;
  for (int j = 0; j + 1 < h; ++j) {
    for (int i = 0; i + 1 < w; ++i) {
      left.push_back(a[j * w + i]), right.push_back(a[j * w + i + 1]);
      up.push_back(a[j * w + i]), down.push_back(a[(j + 1) * w + i]);
    }
  }
  const double bound = 5.0 / std::sqrt(static_cast<double>(left.size()));
  EXPECT_LT(std::abs(rho(left, right)), bound);
  EXPECT_LT(std::abs(rho(up, down)), bound);
  EXPECT_LT(std::abs(rho(a, b)), 5.0 / std::sqrt(static_cast<double>(a.size())));
}

// Blur is computed near the boards only: the same as an independent separable Gaussian (edges
// clamped) of the unblurred rendering over the whole frame, to float rounding (at most one gray
// level after rounding to 8 bits).
TEST(Render, BlurNearTheBoardsEqualsAWholeFrameBlur) {
  const CameraIntrinsics k{500, 500, 90, 319.5, 239.5};
  RenderOptions sharp;
  GrayImage unblurred, blurred;
  const BoardView board = FrontoParallel(-0.1, -0.05);
  RenderOptions o = sharp;
  o.blur_sigma_px = 1.2;
  o.blur_grid = 1;  // The pixel-level blur (the finer grid's is tested below).
  // The unblurred values before rounding: black 20 and white 235 with supersampled edges; round
  // trip through 8 bits loses < 0.5 gray, which the blur then averages (the bound below holds).
  ASSERT_TRUE(RenderFrame(k, {board}, sharp, nullptr, &unblurred, nullptr));
  ASSERT_TRUE(RenderFrame(k, {board}, o, nullptr, &blurred, nullptr));
  const int w = unblurred.width, h = unblurred.height;
  const int radius = static_cast<int>(std::ceil(3 * o.blur_sigma_px));
  std::vector<double> kernel(2 * radius + 1);
  double sum = 0;
  for (int i = -radius; i <= radius; ++i)
    sum += kernel[i + radius] = std::exp(-0.5 * i * i / (o.blur_sigma_px * o.blur_sigma_px));
  for (double& x : kernel) x /= sum;
  std::vector<double> tmp(static_cast<size_t>(w) * h), out(tmp.size());
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      double acc = 0;
      for (int d = -radius; d <= radius; ++d)
        acc += kernel[d + radius] * unblurred.at(std::clamp(i + d, 0, w - 1), j);
      tmp[j * w + i] = acc;
    }
  int worst = 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      double acc = 0;
      for (int d = -radius; d <= radius; ++d)
        acc += kernel[d + radius] * tmp[std::clamp(j + d, 0, h - 1) * w + i];
      worst = std::max(worst, std::abs(static_cast<int>(std::lround(acc)) - blurred.at(i, j)));
    }
  EXPECT_LE(worst, 1);
}

// The blur is the physical one: the scene convolved with the Gaussian PSF, then integrated over
// each pixel. A tag's straight outer edge, turned 10 deg in the image, blurred by sigma: every
// pixel within 3 px of it against the box integral of Phi(distance / sigma), computed here by a
// 64 x 64 midpoint rule over the pixel (independent of the renderer and of the fit's closed form).
// Tolerance: 0.5 gray of 8-bit rounding + 0.5 gray for the finer grid's residual (< 0.35 gray
// at sigma 0.5, m = 6, on a 215-gray contrast: header comment of render.h). The pixel-level blur
// (blur_grid 1) misses by ~19 gray at sigma 0.5 (its edges move with their sub-pixel phase).
// Mutation checked: rendering with m = 1 by default fails this test.
TEST(Render, BlurIsTheGaussianPsfIntegratedOverThePixel) {
  constexpr double kTolGray = 1.0;
  const CameraIntrinsics k{500, 500, 90, 319.5, 239.5};
  BoardView board = FrontoParallel(-0.1, -0.05);
  const double turn = 10 * M_PI / 180;
  board.cam_from_board.rotation =
      Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
      board.cam_from_board.rotation;
  // Tag 0's left edge, board x = 0, black for x > 0; its middle part (away from the corners and
  // the border cell's inner edge 12.5 px away).
  auto pixel_of = [&](double bx, double by) {
    Eigen::Vector2d px;
    ProjectPoint(k, board.cam_from_board * Eigen::Vector3d(bx, by, 0), &px);
    return px;
  };
  const Eigen::Vector2d a = pixel_of(0, 0.06), b = pixel_of(0, 0.14);
  const Eigen::Vector2d along = (b - a).normalized();
  Eigen::Vector2d normal(-along.y(), along.x());  // Towards the black side:
  if (normal.dot(pixel_of(0.01, 0.1) - a) < 0) normal = -normal;
  for (double sigma : {0.5, 1.0}) {
    RenderOptions o;
    o.blur_sigma_px = sigma;
    double worst_fine = 0, worst_pixel_level = 0;
    for (int grid : {0, 1}) {
      o.blur_grid = grid;
      GrayImage image;
      ASSERT_TRUE(RenderFrame(k, {board}, o, nullptr, &image, nullptr));
      double worst = 0;
      for (int j = 0; j < image.height; ++j) {
        for (int i = 0; i < image.width; ++i) {
          const Eigen::Vector2d p(i, j);
          const double d = normal.dot(p - a), t = along.dot(p - a);
          if (std::abs(d) > 3 || t < 0 || t > (b - a).norm()) continue;
          constexpr int kQuad = 64;
          double black = 0;
          for (int qv = 0; qv < kQuad; ++qv) {
            for (int qu = 0; qu < kQuad; ++qu) {
              const Eigen::Vector2d offset((qu + 0.5) / kQuad - 0.5, (qv + 0.5) / kQuad - 0.5);
              black += 0.5 * std::erfc(-(d + normal.dot(offset)) / (sigma * std::sqrt(2.0)));
            }
          }
          black /= kQuad * kQuad;
          const double expected = o.white_gray + (o.black_gray - o.white_gray) * black;
          worst = std::max(worst, std::abs(image.at(i, j) - expected));
        }
      }
      (grid == 0 ? worst_fine : worst_pixel_level) = worst;
    }
    std::printf("sigma %.1f px: worst |rendered - exact| %.2f gray (finer grid), %.2f (pixels)\n",
                sigma, worst_fine, worst_pixel_level);
    EXPECT_LE(worst_fine, kTolGray) << "sigma " << sigma;
  }
}

TEST(Render, UndistortInvertsTheDistortion) {
  CameraIntrinsics k;
  k.k1 = -0.25;
  k.k2 = 0.08;
  k.p1 = 1e-3;
  k.p2 = -2e-3;
  k.k3 = 0.01;
  const auto params = k.Params();
  for (double x = -0.5; x <= 0.5; x += 0.1) {
    for (double y = -0.4; y <= 0.4; y += 0.1) {
      Eigen::Vector2d pixel;
      const Eigen::Vector3d p(x, y, 1.0);
      ASSERT_TRUE(PinholeSkewCamera::Project(params.data(), p.data(), pixel.data()));
      const Eigen::Vector2d distorted = (k.Matrix().inverse() * pixel.homogeneous()).head<2>();
      Eigen::Vector2d undistorted;
      ASSERT_TRUE(UndistortNormalized(k, distorted, &undistorted));
      EXPECT_LT((undistorted - Eigen::Vector2d(x, y)).norm(), 1e-10);
    }
  }
}

}  // namespace
}  // namespace calibench
