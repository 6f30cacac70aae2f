// Chessboard corners (detect/chessboard.h) on a board drawn here, independently of the renderer:
// 10 x 7 squares of 30 px under a perspective homography, painted on an 8x finer canvas with
// OpenCV's sub-pixel polygon fill and averaged to pixels (INTER_AREA: each pixel the mean of its
// 8 x 8 sub-pixels, pixel centres at integers). The 9 x 6 inner corners come back within
// kCornerTolPx of their exact positions, in row-major order from the corner whose square towards
// (1, 1) is dark: the one order of every detector, also when the board is drawn half-turned in the
// image (the cameras of a rig must agree on the board frame). A blank image finds nothing.
#include "detect/chessboard.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

namespace calibench {
namespace {

// cornerSubPix's corners on this board: largest error 0.108 px, mean 0.007 px (measured; the same
// with its stop criterion tightened from 0.1 to 0.001 px, so the error is the estimator's own on
// an 11 x 11 px window under perspective, not its stopping). Each corner is held to 0.15 px and
// their mean to 0.02 px: a half-pixel convention slip, or a corner one square (30 px) off, fails
// either bound.
constexpr double kCornerTolPx = 0.15, kMeanErrorTolPx = 0.02;
constexpr int kFine = 8;

void ExpectCornersWhereTheyAre(bool half_turn) {
  constexpr int kSquaresX = 10, kSquaresY = 7;
  constexpr double kSquarePx = 30;
  // Board (x, y) in squares -> pixels: a homography with some perspective.
  Eigen::Matrix3d h;
  h << kSquarePx * 0.95, kSquarePx * 0.10, 150, kSquarePx * -0.06, kSquarePx * 0.92, 120,
      0.0006 * kSquarePx, 0.0004 * kSquarePx, 1.0;
  auto to_pixel = [&](double x, double y) {
    if (half_turn) x = kSquaresX - x, y = kSquaresY - y;  // The board turned in its plane.
    return Eigen::Vector2d((h * Eigen::Vector3d(x, y, 1)).hnormalized());
  };
  const int width = 640, height = 480;
  cv::Mat fine(height * kFine, width * kFine, CV_8UC1, cv::Scalar(230));
  constexpr int kShift = 4;  // Sub-pixel bits of fillConvexPoly.
  for (int y = -1; y <= kSquaresY; ++y) {
    for (int x = -1; x <= kSquaresX; ++x) {
      const bool white_margin = x < 0 || y < 0 || x >= kSquaresX || y >= kSquaresY;
      if (white_margin || (x + y) % 2 == 1) continue;  // Black where x + y is even.
      std::vector<cv::Point> polygon;
      for (const auto& [dx, dy] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
        const Eigen::Vector2d p = to_pixel(x + dx, y + dy);
        // Fine pixel (I, J) is centred at pixel ((I + 0.5) / kFine - 0.5, ...).
        const Eigen::Vector2d q = kFine * (p.array() + 0.5) - 0.5;
        polygon.emplace_back(static_cast<int>(std::lround(q.x() * (1 << kShift))),
                             static_cast<int>(std::lround(q.y() * (1 << kShift))));
      }
      cv::fillConvexPoly(fine, polygon, cv::Scalar(25), cv::LINE_AA, kShift);
    }
  }
  cv::Mat image;
  cv::resize(fine, image, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  ChessboardOptions options;
  options.cols = kSquaresX - 1, options.rows = kSquaresY - 1;
  std::vector<Eigen::Vector2d> corners;
  std::string how;
  const GrayImageView view(image.data, image.cols, image.rows, static_cast<int>(image.step));
  ASSERT_TRUE(FindChessboardCorners(view, options, &corners, &how));
  ASSERT_EQ(corners.size(), 54u);
  double forward = 0, reverse = 0;  // Largest error of each reading.
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 9; ++c) {
      const Eigen::Vector2d exact = to_pixel(c + 1, r + 1);
      forward = std::max(forward, (corners[r * 9 + c] - exact).norm());
      reverse = std::max(reverse, (corners[53 - (r * 9 + c)] - exact).norm());
    }
  }
  std::printf("%s: largest corner error %.4f px (reverse reading %.1f px)\n", how.c_str(), forward,
              reverse);
  EXPECT_LT(forward, kCornerTolPx) << "half turn " << half_turn << ", reverse " << reverse;
  Eigen::Vector2d mean_error = Eigen::Vector2d::Zero();
  for (int i = 0; i < 54; ++i) {
    const int col = i % 9 + 1, row = i / 9 + 1;
    mean_error += (corners[i] - to_pixel(col, row)) / 54;
  }
  std::printf("mean corner error (%.4f, %.4f) px\n", mean_error.x(), mean_error.y());
  EXPECT_LT(mean_error.norm(), kMeanErrorTolPx);

  if (half_turn) return;
  const cv::Mat blank(height, width, CV_8UC1, cv::Scalar(128));
  const GrayImageView nothing(blank.data, blank.cols, blank.rows, static_cast<int>(blank.step));
  EXPECT_FALSE(FindChessboardCorners(nothing, options, &corners, &how));
  ChessboardOptions bad;
  bad.cols = 1;
  std::string why;
  EXPECT_FALSE(bad.Check(&why));
  EXPECT_NE(why.find("at least 2 x 2"), std::string::npos) << why;
}

TEST(Chessboard, CornersOfADrawnBoardAreFoundWhereTheyAre) { ExpectCornersWhereTheyAre(false); }

TEST(Chessboard, AHalfTurnedBoardReadsInTheSameOrder) { ExpectCornersWhereTheyAre(true); }

}  // namespace
}  // namespace calibench
