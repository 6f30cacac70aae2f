// A rig's frames rendered (sim/rig_render.h) against the rig's own projection: every camera's
// image shows the board where cam_from_rig_c * rig_from_board and camera c's lens put it. Each
// square whose centre projects well inside an image is checked at that pixel: dark where the
// pattern is black (square (i, j), i + j even: sim/checkerboard_image.h), light where white. A
// wrong composition (rig_from_cam for cam_from_rig), a camera rendered through another's lens or
// the noise of one camera drawn into another would put squares of the wrong shade there.
#include "sim/rig_render.h"

#include <gtest/gtest.h>

#include "sim/example_rigs.h"
#include "sim/rig_frames.h"
#include "util/random.h"

namespace calibench {
namespace {

// The shades of CheckerboardImageOptions (25 and 230) with 1 gray level of noise: a square's
// centre is far from an edge, so it is its shade within a few levels. 100 and 155 split them with
// margins of 75 levels.
constexpr double kDarkBelow = 100, kLightAbove = 155;
constexpr double kInsidePx = 12;  // Square centres this far inside the image are checked.

struct ShadeCount {
  int checked = 0, wrong = 0;
};

ShadeCount CheckShades(const RigCamera& camera, const Rigid3& cam_from_board,
                       const CheckerboardPattern& pattern, const GrayImage& image) {
  ShadeCount count;
  for (int j = 0; j < pattern.rows - 1; ++j) {
    for (int i = 0; i < pattern.cols - 1; ++i) {
      // Square (i, j) of the inner grid: its centre in the board frame.
      const Eigen::Vector3d centre((i + 0.5) * pattern.square_m, (j + 0.5) * pattern.square_m, 0);
      Eigen::Vector2d pixel;
      if (!ProjectPoint(camera.intrinsics, cam_from_board * centre, &pixel)) continue;
      if (pixel.x() < kInsidePx || pixel.y() < kInsidePx ||
          pixel.x() > camera.image_width - 1 - kInsidePx ||
          pixel.y() > camera.image_height - 1 - kInsidePx) {
        continue;
      }
      const double gray = image.at(static_cast<int>(std::lround(pixel.x())),
                                   static_cast<int>(std::lround(pixel.y())));
      const bool black = (i + j) % 2 == 0;
      ++count.checked;
      if (black ? gray >= kDarkBelow : gray <= kLightAbove) ++count.wrong;
    }
  }
  return count;
}

TEST(RigRender, EveryCameraSeesTheBoardWhereItsPoseAndLensPutIt) {
  const CameraRig rig = ExampleMixedThreeCameraRig();  // Radtan, double sphere, radtan.
  CheckerboardPattern pattern;
  pattern.cols = 9, pattern.rows = 6, pattern.square_m = 0.04;
  std::string why;
  const auto renderer = RigRenderer::Create(rig, pattern, {}, &why);
  ASSERT_TRUE(renderer) << why;
  RigFramesOptions frames_options;
  frames_options.rows = 6, frames_options.cols = 9, frames_options.spacing_m = 0.04;
  frames_options.num_frames = 6;
  frames_options.whole_board = false;
  frames_options.min_visible_fraction = 0.5;
  Rng pose_rng(11);
  const SyntheticRigFrames frames = MakeRigFrames(rig, frames_options, &pose_rng);
  std::vector<int> checked(rig.NumCameras(), 0);
  Rng noise(12);
  for (const Rigid3& rig_from_board : frames.rig_from_board) {
    std::vector<GrayImage> images;
    ASSERT_TRUE(renderer->Render(rig_from_board, &noise, &images, &why)) << why;
    ASSERT_EQ(static_cast<int>(images.size()), rig.NumCameras());
    for (int c = 0; c < rig.NumCameras(); ++c) {
      const RigCamera& camera = rig.cameras[c];
      ASSERT_EQ(images[c].width, camera.image_width);
      ASSERT_EQ(images[c].height, camera.image_height);
      const ShadeCount count =
          CheckShades(camera, camera.cam_from_rig * rig_from_board, pattern, images[c]);
      EXPECT_EQ(count.wrong, 0) << "camera " << c << ": " << count.wrong << " of " << count.checked
                                << " squares of the wrong shade";
      checked[c] += count.checked;
    }
  }
  // Every camera saw squares in some frame (the frames are drawn so that each camera sees half a
  // board at least once): the test checked each camera's image, not only blank ones.
  for (int c = 0; c < rig.NumCameras(); ++c) EXPECT_GT(checked[c], 20) << "camera " << c;
}

TEST(RigRender, RefusesACameraWithoutImageSize) {
  CameraRig rig = ExampleStereoRig();
  rig.cameras[1].image_width = 0;
  std::string why;
  EXPECT_FALSE(RigRenderer::Create(rig, CheckerboardPattern(), {}, &why));
  EXPECT_FALSE(why.empty());
}

}  // namespace
}  // namespace calibench
