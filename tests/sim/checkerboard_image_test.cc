// Checkerboard images (sim/checkerboard_image.h) against an independent computation: for a pinhole
// camera each square's image is the quadrilateral of its corners' projections, so the image's total
// darkness, sum over pixels of (white - value) / (white - black), is the summed area of the black
// squares' quadrilaterals (shoelace formula) when the background is as white as the margin, and
// its darkness-weighted centroid their area-weighted one; sharp and with a 1 px blur.
#include "sim/checkerboard_image.h"

#include <gtest/gtest.h>

#include "sim/synthetic.h"

namespace calibench {
namespace {

// Pixels on an edge carry two errors: 8-bit rounding (at most 0.5 / 205 px^2 each) and the share
// of the n x n sheared samples, correlated along edges near a pixel axis. The summed error over the
// ~1,700 px of black squares' outlines, measured: 1.08 px^2 at the default 8 x 8, 0.03 at 16 x 16
// (used here), 0.01 at 32 x 32, 0.06 at 64 x 64; with a 1 px blur (3 x 3 sub-pixels of 6 x 6
// samples, blurred and summed) 0.14 px^2. kAreaTolPx2 = 0.5 px^2: one square too many or the
// parity flipped misses it by thousands. The darkness centroid (the image's darkness-weighted mean
// pixel) against the area-weighted mean of the quadrilaterals' centroids tells where the board is
// drawn: a blur conserves it; measured 0.0008 px sharp, 0.0006 px blurred. kCentroidTolPx = 0.005
// px: the board drawn half a pixel off (pixel corners at i instead of i - 0.5) misses it by 0.5 px,
// a finer grid misaligned by half a sub-pixel by 0.17.
constexpr double kAreaTolPx2 = 0.5, kCentroidTolPx = 0.005;

// Area and centroid of a simple polygon (shoelace).
struct PolygonMoments {
  double area = 0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
};
PolygonMoments Moments(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    const double cross = a.x() * b.y() - b.x() * a.y();
    twice += cross;
    sum += (a + b) * cross;
  }
  return {std::abs(twice) / 2, sum / (3 * twice)};
}

class CheckerboardImage : public testing::TestWithParam<double> {};

TEST_P(CheckerboardImage, DarknessIsTheAreaOfTheBlackSquaresImagesWhereTheyAre) {
  const CameraIntrinsics camera{600, 590, 90, 330, 245};
  CheckerboardPattern pattern;
  const Eigen::Vector3d centre = (pattern.Corner(0, 0) + pattern.Corner(5, 8)) / 2;
  const Rigid3 cam_from_board = FacingBoardPose({0.3, -0.25, 0.2}, centre, {0.01, -0.02, 0.5});
  CheckerboardImageOptions options;
  options.background_gray = options.white_gray;
  options.supersample = 16;
  options.blur_sigma_px = GetParam();
  GrayImage image;
  std::string why;
  ASSERT_TRUE(RenderCheckerboard(camera, cam_from_board, pattern, options, nullptr, &image, &why))
      << why;
  double darkness = 0;
  Eigen::Vector2d darkness_centroid = Eigen::Vector2d::Zero();
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double d =
          (options.white_gray - image.at(x, y)) / (options.white_gray - options.black_gray);
      darkness += d;
      darkness_centroid += d * Eigen::Vector2d(x, y);
    }
  }
  darkness_centroid /= darkness;
  double area = 0;
  Eigen::Vector2d area_centroid = Eigen::Vector2d::Zero();
  int black_squares = 0;
  for (int j = -1; j < pattern.rows; ++j) {
    for (int i = -1; i < pattern.cols; ++i) {
      if ((i + j) % 2 != 0) continue;  // Black where i + j is even (header comment).
      std::vector<Eigen::Vector2d> quad;
      for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
        Eigen::Vector2d pixel;
        ASSERT_TRUE(ProjectPoint(camera, cam_from_board * pattern.Corner(j + dj, i + di), &pixel));
        ASSERT_TRUE(pixel.x() > 10 && pixel.y() > 10 && pixel.x() < 629 && pixel.y() < 469);
        quad.push_back(pixel);
      }
      const PolygonMoments m = Moments(quad);
      area += m.area;
      area_centroid += m.area * m.centroid;
      ++black_squares;
    }
  }
  area_centroid /= area;
  std::printf(
      "blur %.1f: %d black squares: area %.3f px^2, darkness %.3f px^2; centroid off by "
      "(%+.5f, %+.5f) px\n",
      GetParam(), black_squares, area, darkness, (darkness_centroid - area_centroid).x(),
      (darkness_centroid - area_centroid).y());
  EXPECT_EQ(black_squares, 35);  // 10 x 7 squares, the origin's square black.
  EXPECT_NEAR(darkness, area, kAreaTolPx2);
  EXPECT_LT((darkness_centroid - area_centroid).norm(), kCentroidTolPx);
  if (GetParam() > 0) return;
  // The square at the origin's upper right is black: its centre pixel is.
  Eigen::Vector2d pixel;
  ASSERT_TRUE(ProjectPoint(camera, cam_from_board * Eigen::Vector3d(0.015, 0.015, 0), &pixel));
  EXPECT_EQ(
      image.at(static_cast<int>(std::lround(pixel.x())), static_cast<int>(std::lround(pixel.y()))),
      options.black_gray);
}
INSTANTIATE_TEST_SUITE_P(SharpAndBlurred, CheckerboardImage, testing::Values(0.0, 1.0));

TEST(CheckerboardImageOptions, BadOptionsAreRefused) {
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
  EXPECT_NE(why.find("inner corners"), std::string::npos);
}

}  // namespace
}  // namespace calibench
