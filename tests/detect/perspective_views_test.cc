// Perspective views of a wide lens (detect/perspective_views.h) and the tags found in them
// (FrameDetector, "Perspective views"): a Kalibr grid near a 190 deg lens's image circle, where
// AprilTag 3 decodes no tag in the image itself.
#include "detect/perspective_views.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "detect/frame_detector.h"
#include "sim/render.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kSide = 800;

// An eucm lens (alpha 0.6, beta 1) whose half field of 95 deg lands 380 px from the principal
// point of an 800 x 800 image (as tests/bench/calibrate_wide_rendered_test.cc's eucm 190 deg).
CameraIntrinsics Eucm190() {
  CameraIntrinsics k;
  k.family = LensFamily::kEucm;
  k.alpha = 0.6, k.beta = 1.0;
  const double f = FocalLengthPuttingRayAt(k, 95, 380);
  k.fku_px = f, k.fkv_px = 1.002 * f, k.u0_px = 401.7, k.v0_px = 397.6;
  return k;
}

TEST(PerspectiveViews, CoverAWideLensFieldAndNoneForAPinhole) {
  CameraIntrinsics pinhole;
  pinhole.fku_px = pinhole.fkv_px = 400, pinhole.u0_px = 399.5, pinhole.v0_px = 399.5;
  EXPECT_TRUE(PerspectiveViewsCovering(pinhole, kSide, kSide).empty());  // 45 deg half field.

  const CameraIntrinsics k = Eucm190();
  const std::vector<PerspectiveView> views = PerspectiveViewsCovering(k, kSide, kSide);
  ASSERT_EQ(views.size(), 17u);  // The axis and two rings: the image's corners see ~130 deg.
  // Every ray of the image (8 px grid) lies 10 deg (a tag's size) or more inside some view
  // (measured: 12.8 deg at worst, in the image's corners).
  double worst_margin_deg = 180;
  for (int y = 0; y < kSide; y += 8) {
    for (int x = 0; x < kSide; x += 8) {
      Eigen::Vector3d ray;
      if (!UnprojectToRay(k, Eigen::Vector2d(x, y), &ray)) continue;
      double best = -180;
      for (const PerspectiveView& v : views) {
        const Eigen::Vector3d in_view = v.cam_from_view.transpose() * ray;
        if (in_view.z() <= 0) continue;
        // Angle to the nearest side of the square view (half field kViewHalfFieldDeg).
        const double to_side =
            kViewHalfFieldDeg - std::max(std::atan2(std::abs(in_view.x()), in_view.z()),
                                         std::atan2(std::abs(in_view.y()), in_view.z())) /
                                    kDeg;
        best = std::max(best, to_side);
      }
      worst_margin_deg = std::min(worst_margin_deg, best);
    }
  }
  EXPECT_GT(worst_margin_deg, 10.0);
  // A view pixel and the image pixel it samples see the same ray.
  const PerspectiveView& v = views[3];
  Eigen::Vector2d image_pixel;
  ASSERT_TRUE(ViewToImage(k, v, Eigen::Vector2d(100.25, 400.5), &image_pixel));
  Eigen::Vector3d ray;
  ASSERT_TRUE(UnprojectToRay(k, image_pixel, &ray));
  EXPECT_LT(ray.normalized().cross(v.RayOf(Eigen::Vector2d(100.25, 400.5)).normalized()).norm(),
            1e-9);
}

// The case they exist for: the board 81 deg off the axis, its tags bent by the lens (a pose drawn
// by tests/bench/calibrate_wide_rendered_test.cc's frame writer: one of 140 boards there).
TEST(PerspectiveViews, FindTheTagsOfABoardAprilTagMissesNearTheImageCircle) {
  const CameraIntrinsics k = Eucm190();
  AprilGrid grid;
  grid.tag_size_m = 0.088;
  grid.black_tag_border = 2;
  grid.corner_squares = true;
  Rigid3 cam_from_board;
  cam_from_board.rotation =
      Eigen::AngleAxisd(
          1.3791105972784734,
          Eigen::Vector3d(0.85262958855871684, 0.15841059106983862, 0.49792456190782325)
              .normalized())
          .toRotationMatrix();
  cam_from_board.translation = {-0.27782297299339309, 0.11744585497794319, -0.29704977111880182};
  RenderOptions ro;
  ro.width = ro.height = kSide;
  ro.blur_sigma_px = 0.8;
  ro.blur_grid = 2;
  ro.noise_sigma_gray = 2;
  std::string why;
  const auto renderer = FrameRenderer::Create(k, ro, &why);
  ASSERT_TRUE(renderer) << why;
  const auto family = TagFamily::Create(grid.family, grid.black_tag_border, &why);
  ASSERT_TRUE(family) << why;
  GrayImage image;
  Rng rng(7);
  ASSERT_TRUE(renderer->Render({{grid, family, cam_from_board}}, &rng, &image, &why)) << why;

  FrameDetectorOptions without_views;
  without_views.camera = k;
  without_views.perspective_views_below_tags = 0;
  FrameDetectorOptions with_views = without_views;
  with_views.perspective_views_below_tags = 4;  // As calibrate --images with a wide lens.
  const auto plain = FrameDetector::Create({grid}, without_views, &why);
  const auto viewing = FrameDetector::Create({grid}, with_views, &why);
  ASSERT_TRUE(plain && viewing) << why;
  EXPECT_TRUE(viewing->FindingUsesCamera());  // A calibration's passes detect again through it.

  DetectionCounts counts;
  // The premise: in the image itself (squares painted through the lens too) no tag is decoded.
  EXPECT_EQ(plain->Detect(image, &counts).size(), 0u);
  const std::vector<Observation> found = viewing->Detect(image, &counts);
  // Measured: 25 tags, 104 corners (of the 36 tags some are cut by the image border).
  EXPECT_GE(found.size(), 80u);
  // Fitted through the lens from the views' corners: as accurate as tags decoded in the image
  // (the lens-aware fit's RMS at this blur and noise is ~0.005 px; 0.03 px bounds every corner).
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  double worst_px = 0;
  for (const Observation& o : found) {
    Eigen::Vector2d truth;
    ASSERT_TRUE(ProjectPoint(k, cam_from_board * corners[o.point_id], &truth));
    worst_px = std::max(worst_px, (o.pixel - truth).norm());
  }
  EXPECT_LT(worst_px, 0.03);
}

}  // namespace
}  // namespace calibench
