// The frame detector (detect/frame_detector.h) on one rendered frame whose tags are placed to
// exercise every rule: a grid fully in view, tags of ids on no grid, an id printed twice, and a tag
// nearer the image border than min_border_distance_px. Counts and point ids are checked against
// the layout, corners against their exact projections, and the two-step form (FindTags, then
// RefineTags) against Detect.
#include "detect/frame_detector.h"

#include <gtest/gtest.h>

#include <map>

#include "sim/render.h"
#include "util/random.h"

namespace calibench {
namespace {

// Corner error of the photometric fit on a sharp, noise-free 30 px tag (measured ~0.005 px): a
// point id mapped to the wrong corner would be 30 px off.
constexpr double kCornerTolPx = 0.05;

struct Layout {
  CameraIntrinsics camera{500, 500, 90, 319.5, 239.5};
  std::vector<BoardView> boards;
};

// A frontal grid whose board origin is at (x, y) m at 1 m in front of the camera (board +y up).
BoardView Frontal(const AprilGrid& grid, const std::shared_ptr<const TagFamily>& family, double x,
                  double y) {
  Eigen::Matrix3d facing = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return {grid, family, {facing, {x, -y, 1.0}}};
}

TEST(FrameDetector, CountsEveryRuleAndMatchesPointIds) {
  const auto family = TagFamily::Create("tag36h11", 1, nullptr);
  ASSERT_NE(family, nullptr);
  AprilGrid grid;  // Ids 0..5: the detector's grid.
  grid.tag_rows = 2, grid.tag_cols = 3, grid.tag_size_m = 0.06;
  AprilGrid strangers = grid;  // Ids 6..11: on no grid of the detector.
  strangers.first_id = 6;
  AprilGrid twin = grid;  // A second id 0.
  twin.tag_rows = twin.tag_cols = 1;
  AprilGrid edge = twin;  // Id 20, 15 px from the right border.
  edge.first_id = 20;
  Layout layout;
  layout.boards = {Frontal(grid, family, -0.35, 0.1), Frontal(strangers, family, 0.05, 0.1),
                   Frontal(twin, family, -0.35, -0.2), Frontal(edge, family, 0.5, -0.2)};
  RenderOptions render;
  render.width = 640, render.height = 480;
  render.noise_sigma_gray = 0;
  std::string why;
  const auto renderer = FrameRenderer::Create(layout.camera, render, &why);
  ASSERT_NE(renderer, nullptr) << why;
  GrayImage image;
  ASSERT_TRUE(renderer->Render(layout.boards, nullptr, &image, &why)) << why;
  // The edge tag's right corners: u = 319.5 + 500 (0.5 + 0.06) = 599.5, 40 px from the border.
  FrameDetectorOptions options;
  options.min_border_distance_px = 45;
  AprilGrid edge_grid = edge;
  const auto detector = FrameDetector::Create({grid, edge_grid}, options, &why);
  ASSERT_NE(detector, nullptr) << why;
  EXPECT_EQ(detector->NumPoints(), 4 * 6 + 4);
  EXPECT_EQ(detector->PointId(20, 3), 4 * 6 + 3);  // The second grid's points follow the first's.
  EXPECT_EQ(detector->PointId(7, 0), -1);
  DetectionCounts counts;
  const std::vector<Observation> observations = detector->Detect(image, &counts);
  EXPECT_EQ(counts.tags, 5);            // Ids 1..5; id 0 is seen twice.
  EXPECT_EQ(counts.duplicate_tags, 2);  // Both detections of id 0 dropped.
  EXPECT_EQ(counts.unknown_tags, 6);
  EXPECT_EQ(counts.border_tags, 1);
  EXPECT_EQ(counts.RefusedTags(), 0);
  ASSERT_EQ(observations.size(), 5u * 4);
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    EXPECT_EQ(o.point_id, static_cast<int>(4 + i));  // Sorted by point id, tags 1..5.
    Eigen::Vector2d exact;
    ASSERT_TRUE(
        ProjectPoint(layout.camera, layout.boards[0].cam_from_board * corners[o.point_id], &exact));
    EXPECT_LT((o.pixel - exact).norm(), kCornerTolPx) << "point " << o.point_id;
    EXPECT_GT(o.crlb_px, 0);
  }
  // Two steps, as calibrate --images runs them: the same observations and counts.
  const GrayImageView view(image);
  const FoundTags found = detector->FindTags(view);
  EXPECT_EQ(found.tags.size(), 5u);
  DetectionCounts two_step;
  const std::vector<Observation> again = detector->RefineTags(view, found, nullptr, &two_step);
  ASSERT_EQ(again.size(), observations.size());
  for (size_t i = 0; i < again.size(); ++i) {
    EXPECT_EQ(again[i].point_id, observations[i].point_id);
    EXPECT_EQ(again[i].pixel, observations[i].pixel);
  }
  EXPECT_EQ(two_step.tags, counts.tags);
  EXPECT_EQ(two_step.duplicate_tags, counts.duplicate_tags);
  EXPECT_EQ(two_step.unknown_tags, counts.unknown_tags);
  EXPECT_EQ(two_step.border_tags, counts.border_tags);
}

}  // namespace
}  // namespace calibench
