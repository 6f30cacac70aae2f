// Method `adaptive` through the registry: on the thesis's noise-free sim 3 it reaches the truth,
// reports its trajectory and excitation; on a barely excited scene it says it is not identifiable.
#include <gtest/gtest.h>

#include "methods/options.h"
#include "metrics/metrics.h"
#include "sim/synthetic.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

// Converged noise-free runs end at ||theta~|| ~ 1e-10 (rounding-limited): the thesis's "exact".
constexpr double kConvergedThetaErr = 1e-6;

class Recorder final : public EstimateSink {
 public:
  void OnSeries(double t, const std::string& series, const Eigen::VectorXd& value) override {
    if (series == kThetaSeries) samples.emplace_back(t, value);
  }
  void OnEstimate(double t, const CameraEstimate& e) override { estimates.emplace_back(t, e); }
  std::vector<std::pair<double, Vector16d>> samples;
  std::vector<std::pair<double, CameraEstimate>> estimates;
};

TEST(AdaptiveMethod, ReachesTheTruthOnThesisSim3AndReportsItsTrajectory) {
  const ThesisSimulation sim = *MakeThesisSimulation(3);
  auto trial = SyntheticTrial::Create(sim.scene, sim.measurements, 1);
  ASSERT_NE(trial, nullptr);
  const std::unique_ptr<Method> method = MakeMethod("adaptive");
  Recorder recorder;
  const MethodResult r = method->Run(trial->input, &recorder);
  ASSERT_TRUE(r.IsUsable()) << r.message;
  const CameraSpec truth{sim.scene.intrinsics, sim.scene.parent_from_cam.rotation,
                         sim.scene.parent_from_cam.translation, false};
  ASSERT_TRUE(r.estimate.theta.has_value());
  EXPECT_LT(ThetaError(TrueTheta(truth), *r.estimate.theta), kConvergedThetaErr);
  ASSERT_TRUE(r.estimate.has_camera);
  EXPECT_NEAR(r.estimate.intrinsics.fku_px, 822, 1e-6);
  EXPECT_NEAR(r.estimate.intrinsics.phi_deg, 87, 1e-8);
  EXPECT_LT((r.estimate.parent_from_cam.translation - truth.x_c).norm(), 1e-8);
  EXPECT_GT(r.outputs.at("pe_min_eig"), 1e-5);
  // The trajectory: t = 0 (the initial guess) then one sample per accepted step, in time order.
  ASSERT_EQ(static_cast<long>(recorder.samples.size()), r.iterations + 1);
  EXPECT_EQ(recorder.samples.front().first, 0.0);
  EXPECT_EQ(recorder.samples.back().first, 240.0);
  for (size_t i = 1; i < recorder.samples.size(); ++i) {
    ASSERT_GT(recorder.samples[i].first, recorder.samples[i - 1].first);
  }
  EXPECT_EQ(recorder.samples.back().second, *r.estimate.theta);
}

// Four points with the small motion: the data are fitted exactly by a wrong theta (the thesis
// needed >= 7 points); the result says so instead of passing for a calibration.
TEST(AdaptiveMethod, FlagsAnUnidentifiableScene) {
  ThesisSimulation sim = *MakeThesisSimulation(3);
  sim.scene.points = ThesisFeaturePoints(4);
  sim.scene.duration_s = 20;
  auto trial = SyntheticTrial::Create(sim.scene, sim.measurements, 1);
  ASSERT_NE(trial, nullptr);
  const MethodResult r = MakeMethod("adaptive")->Run(trial->input, nullptr);
  ASSERT_TRUE(r.IsUsable()) << r.message;
  EXPECT_LT(r.outputs.at("pe_min_eig"), 1e-5);
  EXPECT_NE(r.message.find("not identifiable"), std::string::npos) << r.message;
}

TEST(AdaptiveMethod, OptionsAreChecked) {
  const std::unique_ptr<Method> m = MakeMethod("adaptive");
  std::string why;
  EXPECT_FALSE(SetOption(m.get(), "gamma0", "0", &why));
  EXPECT_NE(why.find("gamma0 must be positive"), std::string::npos) << why;
  EXPECT_FALSE(SetOption(m.get(), "initial_step_s", "1", &why));  // Above max_step_s = 0.1.
  EXPECT_NE(why.find("initial_step_s"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
