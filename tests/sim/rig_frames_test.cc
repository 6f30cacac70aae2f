#include "sim/rig_frames.h"

#include <gtest/gtest.h>

#include "sim/example_rigs.h"

namespace calibench {
namespace {

// Exact pixels are the projections themselves: only rounding (~1e-12 px) separates them.
constexpr double kExactPx = 1e-9;

TEST(RigFrames, OptionsCheckNamesTheField) {
  RigFramesOptions o;
  std::string why;
  EXPECT_TRUE(o.Check(&why));
  o.spacing_m = 0;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("spacing_m"), std::string::npos);
  o = RigFramesOptions();
  o.min_visible_fraction = 1.5;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("min_visible_fraction"), std::string::npos);
}

TEST(RigFrames, StereoFramesAreSeenWholeByBothAndProjectExactly) {
  const CameraRig rig = ExampleStereoRig();
  RigFramesOptions o;
  o.num_frames = 12;
  Rng rng(7);
  const SyntheticRigFrames s = MakeRigFrames(rig, o, &rng);
  ASSERT_EQ(s.frames.size(), 12u);
  ASSERT_EQ(s.rig_from_board.size(), 12u);
  for (size_t f = 0; f < s.frames.size(); ++f) {
    int seen = 0;
    for (int c = 0; c < 2; ++c) {
      const View& view = s.frames[f].views_by_camera[c];
      if (view.points.empty()) continue;
      ++seen;
      EXPECT_EQ(view.points.size(), static_cast<size_t>(o.rows * o.cols));  // whole_board
      for (size_t i = 0; i < view.points.size(); ++i) {
        Eigen::Vector2d pixel;
        ASSERT_TRUE(ProjectPoint(
            rig.cameras[c].intrinsics,
            rig.cameras[c].cam_from_rig * (s.rig_from_board[f] * view.points[i]), &pixel));
        EXPECT_NEAR((pixel - view.pixels[i]).norm(), 0.0, kExactPx);
        EXPECT_GE(view.pixels[i].x(), o.edge_margin_px);
        EXPECT_LE(view.pixels[i].y(), rig.cameras[c].image_height - 1 - o.edge_margin_px);
      }
    }
    EXPECT_GE(seen, o.min_cameras);
  }
}

TEST(RigFrames, SameSeedSameFrames) {
  const CameraRig rig = ExampleStereoRig();
  RigFramesOptions o;
  o.num_frames = 5;
  o.pixel_sigma_px = 0.3;
  Rng a(11), b(11);
  const SyntheticRigFrames sa = MakeRigFrames(rig, o, &a), sb = MakeRigFrames(rig, o, &b);
  ASSERT_EQ(sa.frames.size(), sb.frames.size());
  for (size_t f = 0; f < sa.frames.size(); ++f) {
    EXPECT_EQ(sa.anchor[f], sb.anchor[f]);
    EXPECT_EQ(sa.frames[f].views_by_camera[1].pixels, sb.frames[f].views_by_camera[1].pixels);
  }
}

// The side camera looks 75 degrees off the front camera's axis: no frame reaches both, and every
// frame the side camera sees is shared with the wide camera.
TEST(RigFrames, TriRigSideCameraIsLinkedOnlyThroughTheWideOne) {
  const CameraRig rig = ExampleMixedThreeCameraRig();
  std::string why;
  ASSERT_TRUE(rig.Check(&why)) << why;
  RigFramesOptions o;
  o.num_frames = 30;
  Rng rng(3);
  const SyntheticRigFrames s = MakeRigFrames(rig, o, &rng);
  ASSERT_EQ(s.frames.size(), 30u);
  int front_wide = 0, wide_side = 0;
  for (const RigFrame& frame : s.frames) {
    const bool front = !frame.views_by_camera[0].points.empty();
    const bool wide = !frame.views_by_camera[1].points.empty();
    const bool side = !frame.views_by_camera[2].points.empty();
    EXPECT_FALSE(front && side);
    front_wide += front && wide;
    wide_side += wide && side;
  }
  EXPECT_GT(front_wide, 3);
  EXPECT_GT(wide_side, 3);
}

TEST(RigFrames, PartialBoardsKeepEnoughCorners) {
  const CameraRig rig = ExampleMixedThreeCameraRig();
  RigFramesOptions o;
  o.num_frames = 10;
  o.whole_board = false;
  o.min_visible_fraction = 0.6;
  Rng rng(5);
  const SyntheticRigFrames s = MakeRigFrames(rig, o, &rng);
  ASSERT_EQ(s.frames.size(), 10u);
  for (const RigFrame& frame : s.frames) {
    for (const View& view : frame.views_by_camera) {
      if (!view.points.empty()) {
        EXPECT_GE(view.points.size(), 29u);  // ceil(0.6 * 48)
      }
    }
  }
}

}  // namespace
}  // namespace calibench
