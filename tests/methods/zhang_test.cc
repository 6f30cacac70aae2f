// Methods `zhang` and `zhang_handeye` through the registry, on a noise-free two-board rig: both
// recover the camera (one calibrateCamera shared), hand-eye is refused for a single-axis motion,
// and a scene without boards fails with the reason.
#include <gtest/gtest.h>

#include "methods/options.h"
#include "metrics/metrics.h"
#include "sim/synthetic.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

// cv::calibrateCamera takes float32 points (~1e-7 relative, 4e-5 px here): ~1e-5 deg in its
// per-view poses, and after averaging or the linear hand-eye solve alike (measured 9.0e-6 and
// 9.7e-6 deg; Tsai's own rotation step, singular at this rig's half-turn mount, needed the former
// 2e-4); intrinsics to 1e-6 relative.
constexpr double kFloat32RotationDeg = 5e-5;
constexpr double kFloat32PositionM = 1e-5;

OracleOptions OneFramePerSecond() {
  OracleOptions o;
  o.sample_rate_hz = 1;
  return o;
}

std::unique_ptr<Method> PinholeMethod(const std::string& type) {
  std::unique_ptr<Method> m = MakeMethod(type);
  std::string why;
  EXPECT_TRUE(SetOption(m.get(), "model", "pinhole", &why)) << why;
  return m;
}

TEST(ZhangMethods, RecoverTheRigCameraAndShareOneCalibration) {
  const BoardRigScene rig = SwayingBoardRig();
  auto trial = SyntheticTrial::Create(rig.scene, OneFramePerSecond(), 1, rig.layouts);
  ASSERT_NE(trial, nullptr);
  const CameraSpec truth{rig.scene.intrinsics, rig.scene.parent_from_cam.rotation,
                         rig.scene.parent_from_cam.translation, false};
  const MethodResult zhang = PinholeMethod("zhang")->Run(trial->input, nullptr);
  const MethodResult hand_eye = PinholeMethod("zhang_handeye")->Run(trial->input, nullptr);
  for (const MethodResult* r : {&zhang, &hand_eye}) {
    ASSERT_TRUE(r->IsUsable()) << r->message;
    const CameraErrors e = CameraErrorsAgainst(r->estimate, truth);
    EXPECT_LT(std::abs(e.fku_px) / 822, 1e-6);
    EXPECT_LT(std::abs(e.v0_px) / 239, 1e-6);
    EXPECT_LT(e.rotation_deg, kFloat32RotationDeg);
    EXPECT_LT(e.position_m, kFloat32PositionM);
    EXPECT_TRUE(std::isfinite(r->estimate.fit_rms_px));
    EXPECT_TRUE(std::isnan(r->estimate.intrinsics_std[2]));  // OpenCV fixes the skew.
  }
  // One calibrateCamera for both: the same intrinsics to the bit, the same (its) wall time.
  EXPECT_EQ(zhang.estimate.intrinsics, hand_eye.estimate.intrinsics);
  EXPECT_EQ(zhang.wall_ms, hand_eye.wall_ms);
  EXPECT_NE(zhang.message.find("views"), std::string::npos) << zhang.message;
}

TEST(ZhangMethods, HandEyeRefusesASingleAxisMotion) {
  BoardRigScene rig = SwayingBoardRig();
  TwistProfile twist = rig.scene.motion.profile();
  twist.w_cos.setZero();
  twist.w_sin = Eigen::Vector3d(0.15, 0.2, 0.1);
  Motion::Options options;
  options.duration_s = rig.scene.duration_s;
  rig.scene.motion = Motion(twist, options);
  auto trial = SyntheticTrial::Create(rig.scene, OneFramePerSecond(), 1, rig.layouts);
  ASSERT_NE(trial, nullptr);
  EXPECT_TRUE(PinholeMethod("zhang")->Run(trial->input, nullptr).IsUsable());
  const MethodResult r = PinholeMethod("zhang_handeye")->Run(trial->input, nullptr);
  EXPECT_EQ(r.status, MethodStatus::kFailed);
  EXPECT_NE(r.message.find("degenerate"), std::string::npos) << r.message;
}

TEST(ZhangMethods, NeedPlanarBoards) {
  const ThesisSimulation sim = *MakeThesisSimulation(3);
  auto trial = SyntheticTrial::Create(sim.scene, sim.measurements, 1);
  ASSERT_NE(trial, nullptr);
  const MethodResult r = MakeMethod("zhang")->Run(trial->input, nullptr);
  EXPECT_EQ(r.status, MethodStatus::kFailed);
  EXPECT_NE(r.message.find("zhang needs planar boards"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace calibench
