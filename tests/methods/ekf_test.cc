// Method `ekf` through the registry: on noise-free frames it converges to the truth from a
// perturbed start; with a random walk on the rotation it follows a 0.5 deg pitch step of the
// mount; its options are checked.
#include <gtest/gtest.h>

#include "core/synthetic.h"
#include "methods/options.h"
#include "metrics/metrics.h"
#include "metrics/tracking.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

CameraSpec TruthAt(const SceneTruth& scene, double t) { return scene.CameraAt(t); }

class Recorder final : public EstimateSink {
 public:
  void OnSeries(double, const std::string&, const Eigen::VectorXd&) override {}
  void OnEstimate(double t, const CameraEstimate& e) override { track.Add(t, e), ++count; }
  EstimateTrack track;
  int count = 0;
};

OracleOptions Frames(double rate_hz, double sigma_px) {
  OracleOptions o;
  o.sample_rate_hz = rate_hz;
  o.noise.pixel_sigma_px = sigma_px;
  return o;
}

// The swaying two-board rig, 10 frames/s, noise-free: from the DLT of the first 2 s (exact here)
// the filter has nothing to correct, and from a start 5 px / 0.3 deg off it converges.
TEST(EkfMethod, ConvergesToTheTruthOnNoiseFreeFrames) {
  const BoardRigScene rig = SwayingBoardRig();
  SceneTruth scene = rig.scene;
  scene.duration_s = 20;
  auto trial = SyntheticTrial::Create(scene, Frames(10, 0.0), 1, rig.layouts);
  ASSERT_NE(trial, nullptr);
  const std::unique_ptr<Method> ekf = MakeMethod("ekf");
  std::string why;
  ASSERT_TRUE(SetOption(ekf.get(), "pixel_sigma_px", "0.05", &why)) << why;
  Recorder recorder;
  const MethodResult r = ekf->Run(trial->input, &recorder);
  ASSERT_TRUE(r.IsUsable()) << r.message;
  EXPECT_EQ(recorder.count, r.iterations);  // One estimate per update.
  const CameraErrors e = CameraErrorsAgainst(r.estimate, TruthAt(scene, 20));
  // Noise-free data and an exact start: the updates keep it to rounding (~1e-9 px).
  EXPECT_LT(std::abs(e.fku_px), 1e-6);
  EXPECT_LT(e.rotation_deg, 1e-8);
  ASSERT_EQ(r.estimate.covariance.rows(), CameraEstimate::kCovarianceSize);
  EXPECT_GT(r.estimate.covariance(0, 0), 0.0);
  EXPECT_TRUE(std::isfinite(r.estimate.intrinsics_std[0]));
}

// A pitch step of 0.5 deg at 10 s (oracle, 30 frames/s, 0.2 px noise, 160 corners a frame). With
// ROVIO's random walk of 1e-8 rad^2/s on the rotation the filter follows it: its information
// rate I ~ 1.5e11 rad^-2/s makes its memory sqrt(1 / (q I)) ~ 0.03 s, so 5 s after the step the
// rotation error is far below 0.1 deg. Without process noise (OpenVINS after convergence) P only
// shrinks and the step is never absorbed.
TEST(EkfMethod, FollowsAPitchStepWithARandomWalkOnTheRotation) {
  const BoardRigScene rig = SwayingBoardRig();
  SceneTruth scene = rig.scene;
  scene.duration_s = 15;
  CalibrationChange step;
  step.from_s = step.to_s = 10;
  step.rpy_deg = Eigen::Vector3d(0, 0.5, 0);
  scene.changes = {step};
  auto trial = SyntheticTrial::Create(scene, Frames(30, 0.2), 3, rig.layouts);
  ASSERT_NE(trial, nullptr);
  std::string why;
  double final_rotation_error[2];
  for (int variant = 0; variant < 2; ++variant) {
    const std::unique_ptr<Method> ekf = MakeMethod("ekf");
    ASSERT_TRUE(SetOption(ekf.get(), "pixel_sigma_px", "0.2", &why)) << why;
    ASSERT_TRUE(SetOption(ekf.get(), "q_rotation_rad2_s", variant == 0 ? "1e-8" : "0", &why));
    for (const char* q : {"q_focal_px2_s", "q_center_px2_s", "q_skew_rad2_s", "q_position_m2_s"}) {
      ASSERT_TRUE(SetOption(ekf.get(), q, variant == 0 ? "1e-4" : "0", &why)) << why;
    }
    const MethodResult r = ekf->Run(trial->input, nullptr);
    ASSERT_TRUE(r.IsUsable()) << r.message;
    final_rotation_error[variant] =
        CameraErrorsAgainst(r.estimate, TruthAt(scene, 15)).rotation_deg;
  }
  EXPECT_LT(final_rotation_error[0], 0.1);
  EXPECT_GT(final_rotation_error[1], 0.2);
}

TEST(EkfMethod, OptionsAreChecked) {
  const std::unique_ptr<Method> ekf = MakeMethod("ekf");
  std::string why;
  EXPECT_FALSE(SetOption(ekf.get(), "pixel_sigma_px", "0", &why));
  EXPECT_NE(why.find("pixel_sigma_px must be > 0"), std::string::npos) << why;
  EXPECT_FALSE(SetOption(ekf.get(), "q_rotation_rad2_s", "-1", &why));
  EXPECT_NE(why.find("process noise"), std::string::npos) << why;
  EXPECT_FALSE(SetOption(ekf.get(), "iterations", "0", &why));
  EXPECT_EQ(ekf->Prerequisites(), std::vector<std::string>{"dlt"});
}

}  // namespace
}  // namespace calibench
