#include "batch/dlt.h"

#include <gtest/gtest.h>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

// Noise-free DLT: an SVD of a normalised 2n x 12 system; the bar is 1e-6 relative.
constexpr double kNoiseFreeRelTol = 1e-6;

struct Scene {
  CameraIntrinsics intrinsics;
  Rigid3 cam_from_parent;
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
};

Scene RandomScene(Rng* rng, int n) {
  Scene s;
  s.intrinsics = RandomIntrinsics({}, rng);
  s.cam_from_parent = RandomPose(5, rng);
  for (int i = 0; i < n; ++i) {
    const double z = rng->Uniform(4, 10), y = rng->Uniform(-2, 2);  // Last first: util/random.h.
    const Eigen::Vector3d in_cam(rng->Uniform(-2, 2), y, z);
    s.points.push_back(s.cam_from_parent.Inverse() * in_cam);
    Eigen::Vector2d pixel;
    ProjectPoint(s.intrinsics, in_cam, &pixel);
    s.pixels.push_back(pixel);
  }
  return s;
}

TEST(Dlt, RecoversTheTruthFromNoiseFreeNonCoplanarPoints) {
  Rng rng(17);
  for (int trial = 0; trial < 200; ++trial) {
    const Scene s = RandomScene(&rng, 6 + trial % 40);
    const DltResult r = EstimateDlt(s.points, s.pixels);
    ASSERT_TRUE(r.IsUsable()) << r.message;
    const CameraIntrinsics& k = r.camera.intrinsics;
    EXPECT_NEAR(k.fku_px, s.intrinsics.fku_px, kNoiseFreeRelTol * s.intrinsics.fku_px);
    EXPECT_NEAR(k.fkv_px, s.intrinsics.fkv_px, kNoiseFreeRelTol * s.intrinsics.fkv_px);
    EXPECT_NEAR(k.phi_deg, s.intrinsics.phi_deg, kNoiseFreeRelTol * 90);
    EXPECT_NEAR(k.u0_px, s.intrinsics.u0_px, kNoiseFreeRelTol * s.intrinsics.fku_px);
    EXPECT_NEAR(k.v0_px, s.intrinsics.v0_px, kNoiseFreeRelTol * s.intrinsics.fkv_px);
    EXPECT_LT(
        RotationAngleDeg(r.camera.parent_from_cam.rotation, s.cam_from_parent.Inverse().rotation),
        1e-6);
    // M reprojects every point (relative to the pixel scale, ~1e-12).
    for (size_t i = 0; i < s.points.size(); ++i) {
      EXPECT_LT(((r.m * s.points[i].homogeneous()).hnormalized() - s.pixels[i]).norm(), 1e-6);
    }
  }
}

TEST(Dlt, DegenerateInputFailsWithAReason) {
  Rng rng(3);
  Scene s = RandomScene(&rng, 5);
  DltResult r = EstimateDlt(s.points, s.pixels);
  EXPECT_EQ(r.status, MethodStatus::kFailed);
  EXPECT_NE(r.message.find("at least 6"), std::string::npos) << r.message;

  // Coplanar: a board.
  const CameraIntrinsics k{800, 800, 90, 320, 240};
  SyntheticBoardOptions board;
  board.num_views = 1;
  const SyntheticBoardViews views = MakeBoardViews(k, board, &rng);
  ASSERT_EQ(views.views.size(), 1u);
  r = EstimateDlt(views.views[0].points, views.views[0].pixels);
  EXPECT_EQ(r.status, MethodStatus::kFailed);
  EXPECT_NE(r.message.find("coplanar"), std::string::npos) << r.message;

  // Collinear.
  std::vector<Eigen::Vector3d> line;
  std::vector<Eigen::Vector2d> pixels;
  for (int i = 0; i < 10; ++i) {
    line.emplace_back(0.1 * i, 0.2 * i, 5 + 0.3 * i);
    pixels.emplace_back(320 + i, 240 + 2 * i);
  }
  EXPECT_EQ(EstimateDlt(line, pixels).status, MethodStatus::kFailed);
  // Mismatched sizes.
  pixels.pop_back();
  EXPECT_EQ(EstimateDlt(line, pixels).status, MethodStatus::kFailed);
}

}  // namespace
}  // namespace calibench
