// Method `ekf` through the registry: on noisy frames it converges to the truth from a start
// 5 px / 0.3 deg off; with a random walk on the rotation it follows a 0.5 deg pitch step of the
// mount; its options are checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "methods/options.h"
#include "metrics/metrics.h"
#include "metrics/tracking.h"
#include "sim/synthetic.h"
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

// The swaying two-board rig, 10 frames/s, 0.2 px noise, 20 s. The filter's start (its `init`
// prerequisite, here a stub in place of the DLT) is the truth moved by 5 px in f*ku, f*kv, u0, v0,
// 0.3 deg in R_C and 3 cm in x_C, inside its prior (p0: 10 px, 1 deg, 5 cm). After its 179
// updates (every frame after 2 s) every parameter's error must lie within kSigmas of the filter's
// own reported standard deviation, and that bound must be far below the start's error (else
// "converged" says nothing).
TEST(EkfMethod, ConvergesToTheTruthFromAStartOffTheTruth) {
  const BoardRigScene rig = SwayingBoardRig();
  SceneTruth scene = rig.scene;
  scene.duration_s = 20;
  constexpr double kPixelSigmaPx = 0.2;
  auto trial = SyntheticTrial::Create(scene, Frames(10, kPixelSigmaPx), 1, rig.layouts);
  ASSERT_NE(trial, nullptr);
  const CameraSpec truth = TruthAt(scene, 20);
  constexpr double kStartOffPx = 5.0, kStartOffDeg = 0.3, kStartOffM = 0.03;
  // The independent reference: ceres (maximum likelihood, same parameters: pinhole with skew) on
  // the frames the filter updates with, after its 2 s start window.
  const std::unique_ptr<Method> ceres = MakeMethod("ceres");
  std::string why;
  ASSERT_TRUE(SetOption(ceres.get(), "model", "pinhole", &why)) << why;
  const MethodResult batch =
      ceres->Run(trial->input.Window(std::nextafter(2.0, 3.0), 20.0), nullptr);
  ASSERT_TRUE(batch.IsUsable()) << batch.message;
  const long filter_frames = static_cast<long>(std::count_if(trial->input.Frames().times_s.begin(),
                                                             trial->input.Frames().times_s.end(),
                                                             [](double t) { return t > 2.0; }));
  MethodResult start;
  start.status = MethodStatus::kOk;
  start.estimate.has_camera = true;
  start.estimate.intrinsics = truth.intrinsics;
  start.estimate.intrinsics.fku_px += kStartOffPx;
  start.estimate.intrinsics.fkv_px -= kStartOffPx;
  start.estimate.intrinsics.u0_px += kStartOffPx;
  start.estimate.intrinsics.v0_px -= kStartOffPx;
  start.estimate.parent_from_cam = {
      ExpSO3(Eigen::Vector3d(1, -1, 1).normalized() * kStartOffDeg * M_PI / 180) * truth.r_c,
      truth.x_c + Eigen::Vector3d(kStartOffM, 0, 0)};
  start.estimate.cam_from_parent = start.estimate.parent_from_cam.Inverse();
  std::vector<std::string> asked;
  trial->input.prerequisite = [&](const std::string& name,
                                  const MethodInput&) -> const MethodResult& {
    asked.push_back(name);
    return start;
  };
  const CameraErrors e0 = CameraErrorsAgainst(start.estimate, truth);

  const std::unique_ptr<Method> ekf = MakeMethod("ekf");
  ASSERT_TRUE(SetOption(ekf.get(), "pixel_sigma_px", "0.2", &why)) << why;
  Recorder recorder;
  const MethodResult r = ekf->Run(trial->input, &recorder);
  ASSERT_TRUE(r.IsUsable()) << r.message;
  EXPECT_EQ(asked, std::vector<std::string>{"dlt"});  // It started from the stub.
  EXPECT_EQ(r.iterations, filter_frames);             // Every frame after 2 s.
  EXPECT_EQ(recorder.count, r.iterations);            // One estimate per update.
  const Eigen::MatrixXd& p = r.estimate.covariance;
  ASSERT_EQ(p.rows(), CameraEstimate::kCovarianceSize);
  const CameraErrors e = CameraErrorsAgainst(r.estimate, truth);

  // With the measurement noise modelled as simulated (sigma 0.2 px, white), the filter's error is
  // ~N(0, P) up to linearisation (its steps re-linearise at the current estimate): 4 sigma is
  // exceeded with probability 6e-5 per parameter (chi^2_3 > 16: 1e-3 for the 3-vectors, bounded
  // by sqrt(trace)). Measured at seed 1: 0.9-1.6 sigma (f*ku -0.23 px, sd 0.16 px; R_C 0.010 deg,
  // sd 0.0098 deg; x_C 1.2 mm, sd 0.9 mm).
  constexpr double kSigmas = 4.0;
  const double sd_rot_deg = std::sqrt(p.block<3, 3>(5, 5).trace()) * 180 / M_PI;
  const double sd_pos_m = std::sqrt(p.block<3, 3>(8, 8).trace());
  EXPECT_LT(std::abs(e.fku_px), kSigmas * std::sqrt(p(0, 0)));
  EXPECT_LT(std::abs(e.fkv_px), kSigmas * std::sqrt(p(1, 1)));
  EXPECT_LT(std::abs(e.phi_deg), kSigmas * std::sqrt(p(2, 2)) * 180 / M_PI);
  EXPECT_LT(std::abs(e.u0_px), kSigmas * std::sqrt(p(3, 3)));
  EXPECT_LT(std::abs(e.v0_px), kSigmas * std::sqrt(p(4, 4)));
  EXPECT_LT(e.rotation_deg, kSigmas * sd_rot_deg);
  EXPECT_LT(e.position_m, kSigmas * sd_pos_m);
  // P is honest, checked against the batch ML on the same frames: the filter cannot be surer than
  // the ML (Cramer-Rao; its prior p0 adds < 0.1 % information), and its random walk (q_focal,
  // q_center 1e-4 px^2/s: forgetting) makes it less sure by 1.3-1.5x measured; 2x bounds that, so
  // an inflated P cannot make the 4-sigma checks above vacuous. (ceres's sd uses sigma_hat from
  // its 63k residuals: +-0.3 %, inside kMinSdRatio.)
  constexpr double kMinSdRatio = 0.97, kMaxSdRatio = 2.0;
  for (int i : {0, 1, 3, 4}) {
    const double ratio = std::sqrt(p(i, i)) / batch.estimate.intrinsics_std[i];
    EXPECT_GT(ratio, kMinSdRatio) << i;
    EXPECT_LT(ratio, kMaxSdRatio) << i;
  }
  // The start was really off: its errors exceed the bounds above kMargin times over (measured:
  // 8.0x for f*ku, 7.7x for R_C, 8.3x for x_C).
  constexpr double kMargin = 5.0;
  for (int i : {0, 1, 3, 4}) EXPECT_GT(kStartOffPx, kMargin * kSigmas * std::sqrt(p(i, i))) << i;
  EXPECT_NEAR(e0.rotation_deg, kStartOffDeg, 1e-9);
  EXPECT_GT(e0.rotation_deg, kMargin * kSigmas * sd_rot_deg);
  EXPECT_GT(e0.position_m, kMargin * kSigmas * sd_pos_m);
  EXPECT_TRUE(std::isfinite(r.estimate.intrinsics_std[0]));
  // Mutation checked: ekf.cc's rotation reset with -dtheta (errors 800 px, 97 deg) and its
  // inv_var = 1 / sigma instead of 1 / sigma^2 (sd ratio 2.7 > kMaxSdRatio) both fail here.
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
