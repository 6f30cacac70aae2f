// Method `dlt` through the registry: exact on noise-free non-coplanar points, a failed result that
// names the reason on coplanar ones.
#include <gtest/gtest.h>

#include "metrics/metrics.h"
#include "sim/synthetic.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

TEST(DltMethod, RecoversTheTruthFromNonCoplanarPoints) {
  const ThesisSimulation sim = *MakeThesisSimulation(3);  // 10 points, not coplanar.
  auto trial = SyntheticTrial::Create(sim.scene, sim.measurements, 1);
  ASSERT_NE(trial, nullptr);
  const MethodResult r = MakeMethod("dlt")->Run(trial->input, nullptr);
  ASSERT_TRUE(r.IsUsable()) << r.message;
  ASSERT_TRUE(r.estimate.has_camera && r.estimate.theta.has_value());
  // Noise-free: an SVD on normalised data, ~1e-12 relative.
  EXPECT_NEAR(r.estimate.intrinsics.fku_px, 822, 822 * 1e-9);
  EXPECT_NEAR(r.estimate.intrinsics.phi_deg, 87, 1e-9);
  EXPECT_NEAR(r.estimate.intrinsics.v0_px, 239, 1e-7);
  EXPECT_LT((r.estimate.parent_from_cam.translation - sim.scene.parent_from_cam.translation).norm(),
            1e-9);
  EXPECT_LT(RmsReprojectionPx(r.estimate, trial->input.Frames().views), 1e-8);
}

TEST(DltMethod, CoplanarPointsFailWithTheReason) {
  ThesisSimulation sim = *MakeThesisSimulation(3);
  for (Eigen::Vector3d& p : sim.scene.points) p.y() = 25;  // One plane y = 25 ...
  sim.scene.motion = Motion();                             // ... that stays one (no motion).
  auto trial = SyntheticTrial::Create(sim.scene, sim.measurements, 1);
  ASSERT_NE(trial, nullptr);
  const MethodResult r = MakeMethod("dlt")->Run(trial->input, nullptr);
  EXPECT_EQ(r.status, MethodStatus::kFailed);
  EXPECT_FALSE(r.estimate.has_camera);
  EXPECT_NE(r.message.find("coplanar"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace calibench
