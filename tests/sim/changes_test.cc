// A calibration that changes over time (sim/scene.h): steps and ramps applied to the truth, the
// measurements taken with the truth at their time, the renderer drawing with the intrinsics of the
// frame, and the refusals of bad changes.
#include <gtest/gtest.h>

#include "sim/measurements.h"
#include "sim/render.h"
#include "sim/synthetic.h"

namespace calibench {
namespace {

// Products of a few 3x3 rotations: ~1e-15.
constexpr double kExactTol = 1e-12;

CalibrationChange Step(double at_s, const Eigen::Vector3d& rpy_deg) {
  CalibrationChange c;
  c.from_s = c.to_s = at_s;
  c.rpy_deg = rpy_deg;
  return c;
}

TEST(Changes, StepsAndRampsComposeOnTheInitialCamera) {
  SceneTruth scene = MakeThesisSimulation(3)->scene;
  CalibrationChange ramp;
  ramp.kind = CalibrationChange::Kind::kRamp;
  ramp.from_s = 100;
  ramp.to_s = 200;
  ramp.fku_px = 8.0;
  ramp.x_m = Eigen::Vector3d(0.02, 0, 0);
  scene.changes = {Step(60, {0, 0.5, 0}), ramp, Step(120, {0.3, 0, 0})};
  const Rigid3 initial = scene.parent_from_cam;
  // Before anything: the initial camera.
  EXPECT_EQ(scene.ParentFromCamAt(59.9), initial);
  EXPECT_EQ(scene.IntrinsicsAt(59.9), scene.intrinsics);
  // After the first step: R(0, 0.5 deg, 0) R_C, about the parent's axes.
  const Eigen::Matrix3d pitched = FromRollPitchYawDeg({0, 0.5, 0}) * initial.rotation;
  EXPECT_LT((scene.ParentFromCamAt(60).rotation - pitched).norm(), kExactTol);
  // Half-way through the ramp: half its deltas; the second step on top of the first.
  EXPECT_DOUBLE_EQ(scene.IntrinsicsAt(150).fku_px, scene.intrinsics.fku_px + 4.0);
  EXPECT_LT(
      (scene.ParentFromCamAt(150).translation - initial.translation - Eigen::Vector3d(0.01, 0, 0))
          .norm(),
      kExactTol);
  const Eigen::Matrix3d both = FromRollPitchYawDeg({0.3, 0, 0}) * pitched;
  EXPECT_LT((scene.ParentFromCamAt(150).rotation - both).norm(), kExactTol);
  EXPECT_DOUBLE_EQ(scene.IntrinsicsAt(240).fku_px, scene.intrinsics.fku_px + 8.0);
  EXPECT_EQ(scene.ChangeTimes(), (std::vector<double>{60, 100, 120, 200}));
}

TEST(Changes, MeasurementsUseTheTruthAtTheirTime) {
  SceneTruth scene = MakeThesisSimulation(3)->scene;
  scene.changes = {Step(10, {0, 0.5, 0})};
  for (double rate : {0.0, 30.0}) {  // Continuous and sampled.
    OracleOptions options;
    options.sample_rate_hz = rate;
    const auto source = OracleSource::Create(scene, options, 1, nullptr);
    ASSERT_NE(source, nullptr);
    for (double t : {5.0, 15.0}) {
      // Segment of t; a sampled source holds the frame at the segment's start.
      const std::vector<double>& b = source->Breakpoints();
      const int segment = static_cast<int>(std::upper_bound(b.begin(), b.end(), t) - b.begin()) - 1;
      Frame frame;
      source->Measure(t, segment, &frame);
      const Rigid3 cam_from_parent = scene.CamFromParentAt(frame.time_s);
      for (size_t i = 0; i < frame.pixels.size(); ++i) {
        Eigen::Vector2d expected;
        ASSERT_TRUE(ProjectPoint(scene.IntrinsicsAt(frame.time_s),
                                 cam_from_parent * frame.points_in_parent[i], &expected));
        EXPECT_LT((frame.pixels[i] - expected).norm(), 1e-9) << "t = " << t << " rate " << rate;
      }
    }
    if (rate > 0) continue;
    // Continuous: the step is a breakpoint, and the end of the segment before it still measures
    // the camera before the step (a stage evaluated exactly there belongs to that segment).
    const std::vector<double>& b = source->Breakpoints();
    const auto it = std::find(b.begin(), b.end(), 10.0);
    ASSERT_NE(it, b.end());
    Frame before, after;
    source->Measure(10.0, static_cast<int>(it - b.begin()) - 1, &before);
    source->Measure(10.0, static_cast<int>(it - b.begin()), &after);
    EXPECT_GT((before.pixels[0] - after.pixels[0]).norm(), 1.0);  // 0.5 deg ~ 7 px.
  }
}

// Rendering with the intrinsics of the frame through the table of the initial camera (the affine
// ray map) draws the image a renderer built for those intrinsics draws: the same rays up to
// rounding, so at most a gray level differs, in a few edge pixels.
TEST(Changes, RendererDrawsWithTheFramesIntrinsics) {
  const CameraIntrinsics initial{800, 800, 90, 320, 240};
  CameraIntrinsics warmer = initial;
  warmer.fku_px += 8;
  warmer.fkv_px += 8;
  warmer.u0_px += 1.5;
  BoardView view = SixByFiveTagGrid();
  view.cam_from_board = FacingBoardPose({0.2, -0.1, 0}, {0.15, 0.12, 0}, {0, 0, 0.6});
  RenderOptions options;
  const auto table = FrameRenderer::Create(initial, options, nullptr);
  const auto fresh = FrameRenderer::Create(warmer, options, nullptr);
  GrayImage mapped, direct, unchanged;
  ASSERT_TRUE(table->Render({view}, nullptr, &mapped, nullptr, &warmer));
  ASSERT_TRUE(fresh->Render({view}, nullptr, &direct, nullptr));
  ASSERT_TRUE(table->Render({view}, nullptr, &unchanged, nullptr));
  int differing = 0, max_difference = 0, moved = 0;
  for (size_t k = 0; k < direct.pixels.size(); ++k) {
    const int d = std::abs(mapped.pixels[k] - direct.pixels[k]);
    differing += d > 0;
    max_difference = std::max(max_difference, d);
    moved += unchanged.pixels[k] != direct.pixels[k];
  }
  EXPECT_LE(max_difference, 1);
  EXPECT_LT(differing, 50);
  EXPECT_GT(moved, 1000);  // The change really moves the image.
}

TEST(Changes, BadChangesAreRefused) {
  SceneTruth scene = MakeThesisSimulation(3)->scene;
  std::string why;
  scene.changes = {Step(300, {0, 0.5, 0})};  // After the run's 240 s.
  EXPECT_FALSE(scene.Check(&why));
  EXPECT_NE(why.find("changes[0]: at_s = 300 s is outside the run [0, 240] s"), std::string::npos)
      << why;
  CalibrationChange a, b;
  a.kind = b.kind = CalibrationChange::Kind::kRamp;
  a.from_s = 10, a.to_s = 50, a.fku_px = 2;
  b.from_s = 40, b.to_s = 60, b.fku_px = 3;
  scene.changes = {a, b};
  EXPECT_FALSE(scene.Check(&why));
  EXPECT_NE(why.find("changes[0] and changes[1] both ramp fku_px over overlapping intervals"),
            std::string::npos)
      << why;
  b.fku_px = 0, b.fkv_px = 3;  // Another quantity: fine.
  scene.changes = {a, b};
  EXPECT_TRUE(scene.Check(&why)) << why;
  CalibrationChange nan = Step(10, {0, std::nan(""), 0});
  scene.changes = {nan};
  EXPECT_FALSE(scene.Check(&why));
  EXPECT_NE(why.find("every delta must be finite"), std::string::npos) << why;
  scene.changes = {Step(10, {0, 0, 0})};
  EXPECT_FALSE(scene.Check(&why));
  EXPECT_NE(why.find("changes nothing"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
