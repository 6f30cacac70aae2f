// The frame detector (detect/frame_detector.h) on one rendered frame whose tags are placed to
// exercise every rule: a grid fully in view, tags of ids on no grid, an id printed twice, and a tag
// nearer the image border than min_border_distance_px. Counts and point ids are checked against
// the layout, corners against their exact projections, and the two-step form (FindTags, then
// RefineTags) against Detect.
#include "detect/frame_detector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <set>

#include "sim/render.h"
#include "util/random.h"

namespace calibench {
namespace {

// A 3 x 4 grid of 5 cm tag36h11 tags facing the camera, turned `yaw_deg` about its y axis, its
// origin at `origin_in_cam` (m).
BoardView YawedGrid(double yaw_deg, const Eigen::Vector3d& origin_in_cam) {
  AprilGrid grid;
  grid.tag_rows = 3, grid.tag_cols = 4, grid.tag_size_m = 0.05;
  const Eigen::Matrix3d yawed =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() *
      Eigen::Vector3d(1, -1, -1).asDiagonal();
  return {grid, TagFamily::Create("tag36h11", 1, nullptr), {yawed, origin_in_cam}};
}

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
  // Ids 1..5 decoded; id 0 is seen twice (both detections dropped) and then fitted where its
  // neighbours put it on the grid: the grid's own tag 0, not the twin.
  EXPECT_EQ(counts.tags, 6);
  EXPECT_EQ(counts.predicted_tags, 1);
  EXPECT_EQ(counts.refused_predictions, 0);
  EXPECT_EQ(counts.duplicate_tags, 2);
  EXPECT_EQ(counts.unknown_tags, 6);
  EXPECT_EQ(counts.border_tags, 1);
  EXPECT_EQ(counts.RefusedTags(), 0);
  ASSERT_EQ(observations.size(), 6u * 4);
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    EXPECT_EQ(o.point_id, static_cast<int>(i));  // Sorted by point id, tags 0..5.
    Eigen::Vector2d exact;
    ASSERT_TRUE(
        ProjectPoint(layout.camera, layout.boards[0].cam_from_board * corners[o.point_id], &exact));
    EXPECT_LT((o.pixel - exact).norm(), kCornerTolPx) << "point " << o.point_id;
    EXPECT_GT(o.crlb_px, 0);
  }
  // Two steps, as calibrate --images runs them: the same observations and counts.
  const GrayImageView view(image);
  const FoundTags found = detector->FindTags(view);
  EXPECT_EQ(found.tags.size(), 5u);  // The prediction belongs to the refinement.
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
  EXPECT_EQ(two_step.predicted_tags, counts.predicted_tags);
}

// Tags the detector missed are fitted where their neighbours put them, and only where the pixels
// show the tag: a 3 x 4 grid at 30 degrees of yaw, noise 2 gray levels; six of its decoded tags
// are taken out of FindTags' result as if AprilTag 3 had missed them, then one of those is half
// covered (a gray rectangle) and another has its data cells painted white. A decoded tag whose
// corner AprilTag 3 put 3 px off (beyond the fit's max_correction_px of 1.5) is refused from
// there and fitted again where its neighbours put it.
TEST(FrameDetector, PredictsMissedTagsAndRefusesTagsThePixelsDoNotShow) {
  const BoardView board = YawedGrid(30, {-0.12, 0.1, 0.8});
  ASSERT_NE(board.family, nullptr);
  const AprilGrid& grid = board.grid;
  const CameraIntrinsics camera{500, 500, 90, 319.5, 239.5};
  RenderOptions render;
  render.width = 640, render.height = 480;
  render.noise_sigma_gray = 2;
  std::string why;
  const auto renderer = FrameRenderer::Create(camera, render, &why);
  ASSERT_NE(renderer, nullptr) << why;
  GrayImage image;
  Rng rng(7);
  ASSERT_TRUE(renderer->Render({board}, &rng, &image, &why)) << why;
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  auto exact = [&](int point) {
    Eigen::Vector2d pixel;
    EXPECT_TRUE(ProjectPoint(camera, board.cam_from_board * corners[point], &pixel));
    return pixel;
  };
  // Tag 5: its left half under a mid-gray rectangle. Tag 10: the inside of its border ring
  // (tag coordinates [1/8, 7/8]^2 of the 8-cell square) white.
  auto tag_point = [&](int tag, double x, double y) {
    const Eigen::Vector2d p0 = exact(4 * tag), p1 = exact(4 * tag + 1), p3 = exact(4 * tag + 3);
    return cv::Point(static_cast<int>(std::lround(p0.x() + x * (p1 - p0).x() + y * (p3 - p0).x())),
                     static_cast<int>(std::lround(p0.y() + x * (p1 - p0).y() + y * (p3 - p0).y())));
  };
  cv::Mat mat(image.height, image.width, CV_8UC1, image.pixels.data());
  const std::vector<cv::Point> covered = {tag_point(5, -0.15, -0.15), tag_point(5, 0.5, -0.15),
                                          tag_point(5, 0.5, 1.15), tag_point(5, -0.15, 1.15)};
  cv::fillConvexPoly(mat, covered, cv::Scalar(128));
  const std::vector<cv::Point> inside = {tag_point(10, 0.125, 0.125), tag_point(10, 0.875, 0.125),
                                         tag_point(10, 0.875, 0.875), tag_point(10, 0.125, 0.875)};
  cv::fillConvexPoly(mat, inside, cv::Scalar(render.white_gray));

  FrameDetectorOptions options;
  const auto detector = FrameDetector::Create({grid}, options, &why);
  ASSERT_NE(detector, nullptr) << why;
  const GrayImageView view(image);
  FoundTags found = detector->FindTags(view);
  // The painted tags do not decode; every other tag does.
  ASSERT_EQ(found.tags.size(), 10u);
  const std::set<int> missed = {0, 3, 6, 7, 5, 10};
  FoundTags kept;
  for (size_t t = 0; t < found.tags.size(); ++t) {
    if (missed.count(found.tags[t].id) > 0) continue;
    kept.tags.push_back(found.tags[t]);
    kept.from_copy.push_back(false);
  }
  ASSERT_EQ(kept.tags.size(), 6u);
  const auto thrown_off = std::find_if(kept.tags.begin(), kept.tags.end(),
                                       [](const TagDetection& tag) { return tag.id == 1; });
  ASSERT_NE(thrown_off, kept.tags.end());
  thrown_off->corners[2] += Eigen::Vector2d(3.0, 0.0);
  DetectionCounts counts;
  const std::vector<Observation> observations = detector->RefineTags(view, kept, nullptr, &counts);
  EXPECT_EQ(counts.tags, 10);
  EXPECT_EQ(counts.predicted_tags, 4);       // Tags 0, 3, 6 and 7.
  EXPECT_EQ(counts.refitted_tags, 1);        // Tag 1.
  EXPECT_EQ(counts.RefusedTags(), 0);        // Tag 1's refusal undone.
  EXPECT_EQ(counts.refused_predictions, 2);  // Tags 5 and 10.
  ASSERT_EQ(observations.size(), 10u * 4);
  std::set<int> tags_seen;
  for (const Observation& o : observations) {
    tags_seen.insert(o.point_id / 4);
    EXPECT_LT((o.pixel - exact(o.point_id)).norm(), kCornerTolPx) << "point " << o.point_id;
  }
  EXPECT_EQ(tags_seen.count(5), 0u);
  EXPECT_EQ(tags_seen.count(10), 0u);

  // Off: the tags found are all there is.
  options.predict_missing_tags = false;
  const auto plain = FrameDetector::Create({grid}, options, &why);
  ASSERT_NE(plain, nullptr) << why;
  EXPECT_EQ(plain->RefineTags(view, kept, nullptr, &counts).size(), 5u * 4);
  EXPECT_EQ(counts.predicted_tags, 0);
  EXPECT_EQ(counts.refitted_tags, 0);
  EXPECT_EQ(counts.refused_tags[static_cast<int>(FitFailure::kMoved)] +
                counts.refused_tags[static_cast<int>(FitFailure::kNotConverged)],
            1);  // Tag 1, refused from its thrown-off corner.
}

// Through a lens that distorts, a predicted tag is not placed farther off the axis than the fitted
// tags reach; a decoded tag whose fit failed from a thrown-off corner is, since AprilTag 3 decoded
// it there: the grid's tag farthest off the axis, its corner put 3 px off, comes back within
// kCornerTolPx of its projection, counted as refitted.
TEST(FrameDetector, RefitsADecodedTagBeyondTheFittedTagsThroughALens) {
  const BoardView board = YawedGrid(20, {-0.05, 0.06, 0.7});
  ASSERT_NE(board.family, nullptr);
  const AprilGrid& grid = board.grid;
  const CameraIntrinsics camera{500, 500, 90, 319.5, 239.5, -0.15, 0.02};
  RenderOptions render;
  render.width = 640, render.height = 480;
  std::string why;
  GrayImage image;
  ASSERT_TRUE(RenderFrame(camera, {board}, render, nullptr, &image, &why)) << why;
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  auto exact = [&](int point) {
    Eigen::Vector2d pixel;
    EXPECT_TRUE(ProjectPoint(camera, board.cam_from_board * corners[point], &pixel));
    return pixel;
  };
  auto off_axis = [&](int point) {
    const Eigen::Vector3d p = board.cam_from_board * corners[point];
    return std::acos(p.normalized().z());
  };
  int farthest = 0;  // The tag with the corner farthest off the axis.
  for (int point = 0; point < 4 * grid.NumTags(); ++point) {
    if (off_axis(point) > off_axis(4 * farthest) && off_axis(point) > off_axis(4 * farthest + 1) &&
        off_axis(point) > off_axis(4 * farthest + 2) &&
        off_axis(point) > off_axis(4 * farthest + 3))
      farthest = point / 4;
  }
  FrameDetectorOptions options;
  options.camera = camera;
  const auto detector = FrameDetector::Create({grid}, options, &why);
  ASSERT_NE(detector, nullptr) << why;
  const GrayImageView view(image);
  FoundTags found = detector->FindTags(view);
  ASSERT_EQ(found.tags.size(), 12u);
  for (TagDetection& tag : found.tags) {
    if (tag.id != farthest) continue;
    // Its corner farthest off the axis, 3 px farther out.
    int k = 0;
    for (int c = 1; c < 4; ++c) {
      if (off_axis(4 * farthest + c) > off_axis(4 * farthest + k)) k = c;
    }
    const Eigen::Vector2d out = (tag.corners[k] - Eigen::Vector2d(319.5, 239.5)).normalized();
    tag.corners[k] += 3.0 * out;
  }
  DetectionCounts counts;
  const std::vector<Observation> observations = detector->RefineTags(view, found, &camera, &counts);
  EXPECT_EQ(counts.tags, 12);
  EXPECT_EQ(counts.refitted_tags, 1) << "tag " << farthest;
  EXPECT_EQ(counts.RefusedTags(), 0);
  ASSERT_EQ(observations.size(), 12u * 4);
  for (const Observation& o : observations) {
    EXPECT_LT((o.pixel - exact(o.point_id)).norm(), kCornerTolPx) << "point " << o.point_id;
  }
}

}  // namespace
}  // namespace calibench
