#include "core/render.h"

#include <gtest/gtest.h>

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

// The pixel-centre convention: an edge placed exactly between two sub-samples of pixel 100
// (u = 99.5 + 45/64) is read back from the pixel's area fraction to 0.01 px (quantisation to
// 8 bits with black 0 / white 255 leaves 0.002 px).
TEST(Render, EdgeLandsWhereTheCameraModelPutsIt) {
  const CameraIntrinsics k{500, 500, 90, 319.5, 239.5};
  const double edge_u = 99.5 + 45.0 / 64.0;
  // Tag 0's left edge is board x = 0: u = 500 * tx + 319.5.
  BoardView b = FrontoParallel((edge_u - 319.5) / 500, -0.1);
  RenderOptions o;
  o.supersample = 64;
  o.black_gray = 0;
  o.white_gray = 255;
  GrayImage img;
  std::string why;
  ASSERT_TRUE(RenderFrame(k, {b}, o, nullptr, &img, &why)) << why;
  // Row through the lower part of tag 0's black border (board y in (0, s/8)).
  // v = 239.5 + 500 * (-y - 0.1): board y = s/16 = 0.0125 m is v = 183.25.
  const int row = static_cast<int>(std::lround(239.5 + 500 * (-0.0125 - 0.1)));
  EXPECT_EQ(img.at(98, row), 255);  // White margin left of the tag.
  EXPECT_EQ(img.at(102, row), 0);   // Black border.
  const double black_fraction = 1.0 - img.at(100, row) / 255.0;
  const double estimated_edge = 100.5 - black_fraction;
  EXPECT_NEAR(estimated_edge, edge_u, 0.01);
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
