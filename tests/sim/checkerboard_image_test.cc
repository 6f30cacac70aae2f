// Checkerboard images (sim/checkerboard_image.h) against an independent computation: for a pinhole
// camera each square's image is the quadrilateral of its corners' projections, so the image's total
// darkness, sum over pixels of (white - value) / (white - black), is the summed area of the black
// squares' quadrilaterals (shoelace formula) when the background is as white as the margin.
#include "sim/checkerboard_image.h"

#include <gtest/gtest.h>

#include "sim/synthetic.h"

namespace calibench {
namespace {

// Pixels on an edge carry two errors: 8-bit rounding (at most 0.5 / 205 px^2 each) and the share
// of the n x n sheared samples, correlated along edges near a pixel axis. The summed error over the
// ~1,700 px of black squares' outlines, measured: 1.08 px^2 at the default 8 x 8, 0.03 at 16 x 16
// (used here), 0.01 at 32 x 32, 0.06 at 64 x 64. 0.5 px^2 is 1/3,000 px along those outlines: a
// board drawn half a pixel off, one square too many or the parity flipped misses it by hundreds.
constexpr double kAreaTolPx2 = 0.5;

double ShoelaceArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return std::abs(twice) / 2;
}

TEST(CheckerboardImage, DarknessIsTheAreaOfTheBlackSquaresImages) {
  const CameraIntrinsics camera{600, 590, 90, 330, 245};
  CheckerboardPattern pattern;
  const Eigen::Vector3d centre = (pattern.Corner(0, 0) + pattern.Corner(5, 8)) / 2;
  const Rigid3 cam_from_board = FacingBoardPose({0.3, -0.25, 0.2}, centre, {0.01, -0.02, 0.5});
  CheckerboardImageOptions options;
  options.background_gray = options.white_gray;
  options.supersample = 16;
  GrayImage image;
  std::string why;
  ASSERT_TRUE(RenderCheckerboard(camera, cam_from_board, pattern, options, nullptr, &image, &why))
      << why;
  double darkness = 0;
  for (const uint8_t v : image.pixels) {
    darkness += (options.white_gray - v) / (options.white_gray - options.black_gray);
  }
  double area = 0;
  int black_squares = 0;
  for (int j = -1; j < pattern.rows; ++j) {
    for (int i = -1; i < pattern.cols; ++i) {
      if ((i + j) % 2 != 0) continue;  // Black where i + j is even (header comment).
      std::vector<Eigen::Vector2d> quad;
      for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
        Eigen::Vector2d pixel;
        ASSERT_TRUE(ProjectPoint(camera, cam_from_board * pattern.Corner(j + dj, i + di), &pixel));
        ASSERT_TRUE(pixel.x() > 0 && pixel.y() > 0 && pixel.x() < 639 && pixel.y() < 479);
        quad.push_back(pixel);
      }
      area += ShoelaceArea(quad);
      ++black_squares;
    }
  }
  std::printf("%d black squares: area %.3f px^2, darkness %.3f px^2\n", black_squares, area,
              darkness);
  EXPECT_EQ(black_squares, 35);  // 10 x 7 squares, the origin's square black.
  EXPECT_NEAR(darkness, area, kAreaTolPx2);
  // The square at the origin's upper right is black: its centre pixel is.
  Eigen::Vector2d pixel;
  ASSERT_TRUE(ProjectPoint(camera, cam_from_board * Eigen::Vector3d(0.015, 0.015, 0), &pixel));
  EXPECT_EQ(
      image.at(static_cast<int>(std::lround(pixel.x())), static_cast<int>(std::lround(pixel.y()))),
      options.black_gray);
}

TEST(CheckerboardImage, BadOptionsAreRefused) {
  GrayImage image;
  std::string why;
  CheckerboardImageOptions options;
  options.supersample = 0;
  EXPECT_FALSE(RenderCheckerboard({}, {}, {}, options, nullptr, &image, &why));
  EXPECT_NE(why.find("supersample"), std::string::npos);
  options = {};
  options.noise_sigma_gray = 2;
  EXPECT_FALSE(RenderCheckerboard({}, {}, {}, options, nullptr, &image, &why));
  EXPECT_NE(why.find("random generator"), std::string::npos);
  CheckerboardPattern one_row;
  one_row.rows = 1;
  EXPECT_FALSE(RenderCheckerboard({}, {}, one_row, {}, nullptr, &image, &why));
  EXPECT_NE(why.find("2 x 2"), std::string::npos);
}

}  // namespace
}  // namespace calibench
