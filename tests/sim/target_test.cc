// Calibration targets (sim/target.h) against their definitions, computed here independently:
// a planar board row by row, and an AprilGrid as Kalibr numbers the same corners (row-major on a
// 2 tag_rows x 2 tag_cols grid, GridCalibrationTargetAprilgrid.cpp) mapped to calibench's tag-major
// order; each placed by its pose; the rig's concatenation; bad values refused with a reason.
#include "sim/target.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr double kExact = 1e-15;      // Positions are products and sums of the same doubles.
constexpr double kPlacedTol = 1e-12;  // One rotation and translation of metre-sized points.

TEST(PlanarBoard, CornersAreRowByRowAndPlacedByTheirPose) {
  PlanarBoard board;
  board.rows = 3, board.cols = 4, board.spacing_m = 0.07;
  Rng rng(4);
  board.points_from_board = RandomPose(1.0, &rng);
  const std::vector<Eigen::Vector3d> in_board = board.CornersInBoard();
  const std::vector<Eigen::Vector3d> placed = board.CornersInPointsFrame();
  ASSERT_EQ(in_board.size(), 12u);
  ASSERT_EQ(board.NumCorners(), 12);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector3d want(c * 0.07, r * 0.07, 0);
      EXPECT_LT((in_board[r * 4 + c] - want).norm(), kExact) << r << ", " << c;
      const Eigen::Vector3d moved =
          board.points_from_board.rotation * want + board.points_from_board.translation;
      EXPECT_LT((placed[r * 4 + c] - moved).norm(), kPlacedTol);
    }
  }
  PlanarBoard second = board;
  second.points_from_board.translation.x() += 1;
  const std::vector<Eigen::Vector3d> rig = RigCorners({board, second});
  ASSERT_EQ(rig.size(), 24u);
  EXPECT_LT((rig[12] - placed[0] - Eigen::Vector3d(1, 0, 0)).norm(), kPlacedTol);
}

TEST(AprilGrid, CornersAreKalibrsInTagOrder) {
  AprilGrid grid;
  grid.tag_rows = 3, grid.tag_cols = 5, grid.tag_size_m = 0.04, grid.tag_spacing = 0.25;
  const double s = 0.04, p = 0.04 * 1.25;
  EXPECT_DOUBLE_EQ(grid.Pitch(), p);
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  ASSERT_EQ(corners.size(), 4u * 15);
  // Kalibr's point (R, C) of the 6 x 10 grid: x = (C / 2) p + (C % 2) s, y likewise in R.
  auto kalibr = [&](int row, int col) {
    // NOLINTNEXTLINE(bugprone-integer-division): Kalibr's formula counts whole pitches, C / 2.
    return Eigen::Vector3d((col / 2) * p + (col % 2) * s, (row / 2) * p + (row % 2) * s, 0);
  };
  for (int i = 0; i < grid.NumTags(); ++i) {
    const int r = i / 5, c = i % 5;  // Id first_id + r tag_cols + c, r upwards.
    // Corner k: bottom-left, bottom-right, top-right, top-left.
    const int dr[4] = {0, 0, 1, 1}, dc[4] = {0, 1, 1, 0};
    for (int k = 0; k < 4; ++k) {
      EXPECT_LT((corners[4 * i + k] - kalibr(2 * r + dr[k], 2 * c + dc[k])).norm(), kExact)
          << "tag " << i << " corner " << k;
    }
  }
  // Placed by the pose.
  Rng rng(9);
  grid.points_from_board = RandomPose(0.5, &rng);
  const std::vector<Eigen::Vector3d> placed = grid.CornersInPointsFrame();
  for (size_t j = 0; j < corners.size(); ++j) {
    EXPECT_LT((placed[j] -
               (grid.points_from_board.rotation * corners[j] + grid.points_from_board.translation))
                  .norm(),
              kPlacedTol);
  }
}

TEST(Targets, BadValuesAreRefusedWithAReason) {
  struct Case {
    AprilGrid grid;
    const char* reason;
  };
  std::vector<Case> cases(10);
  cases[0].grid.tag_rows = 0, cases[0].reason = "at least one tag";
  cases[1].grid.tag_size_m = -1, cases[1].reason = "tag_size_m must be positive";
  cases[2].grid.tag_spacing = 0, cases[2].reason = "tag_spacing must be positive";
  cases[3].grid.first_id = -1, cases[3].reason = "first_id must be >= 0";
  cases[4].grid.black_tag_border = 3, cases[4].reason = "black_tag_border must be 1";
  cases[5].grid.points_from_board.rotation(0, 0) = 2, cases[5].reason = "invalid rotation";
  cases[6].grid.family = "tag99h9", cases[6].reason = "unknown AprilTag family 'tag99h9'";
  // Ids past the family's 587 codes: by the offset, by the count, and by a count past an int.
  cases[7].grid.first_id = 552, cases[7].reason = "587 codes (ids 0..586): 6 x 6 tags from id 552";
  cases[8].grid.tag_rows = 17, cases[8].grid.tag_cols = 35;
  cases[8].reason = "17 x 35 tags from id 0 need ids up to 594";
  cases[9].grid.tag_rows = 9, cases[9].grid.tag_cols = 677777777;
  cases[9].reason = "need ids up to 6099999992";
  for (const Case& c : cases) {
    std::string why;
    EXPECT_FALSE(c.grid.Check(&why)) << c.reason;
    EXPECT_NE(why.find(c.reason), std::string::npos) << why;
  }
  EXPECT_TRUE(AprilGrid().Check(nullptr));
  AprilGrid every_code;  // Ids 0..586: all of tag36h11.
  every_code.first_id = 551;
  EXPECT_TRUE(every_code.Check(nullptr));
  PlanarBoard board;
  std::string why;
  EXPECT_TRUE(board.Check(&why)) << why;
  board.cols = 1;
  EXPECT_FALSE(board.Check(&why));
  EXPECT_NE(why.find("2 x 2 corners"), std::string::npos) << why;
  board.cols = 4, board.spacing_m = std::nan("");
  EXPECT_FALSE(board.Check(&why));
  EXPECT_NE(why.find("spacing_m must be positive"), std::string::npos) << why;
  board.spacing_m = 0.1, board.rows = kMaxCornersPerSide + 1;
  EXPECT_FALSE(board.Check(&why));
  EXPECT_NE(why.find("at most 10000 corners a side"), std::string::npos) << why;
  board.rows = kMaxCornersPerSide;
  EXPECT_TRUE(board.Check(&why)) << why;
}

}  // namespace
}  // namespace calibench
