// The joint rig EKF (methods/ekf_rig.h) on oracle frames of a stereo pair: the swaying two-board
// scene (sim/synthetic.h's SwayingBoardRig) seen by camera 0 and by a camera 1 turned and shifted
// as configs/dynamic/rig_pair.yaml's right camera, both measured at the same instants with white
// Gaussian pixel noise. Each camera starts from its own DLT on the first 2 s (method ekf's default
// init). Checked: the NEES of the relative pose over Monte Carlo trials lies in its chi-square
// band; the relative rotation converges to the truth; after a 0.3 deg relative pitch step
// (configs/dynamic/rig_step.yaml) it re-converges; the options are checked.
#include "methods/ekf_rig.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "metrics/tracking.h"
#include "sim/synthetic.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180;
constexpr double kPixelSigmaPx = 0.2;
constexpr double kStartWindowS = 2.0;  // Method ekf's init_window_s default.

// Camera 1 of rig_pair.yaml: 0.12 m along camera 0's x axis (t = -0.12 m), turned by about
// 0.5 deg, its own intrinsics.
SceneTruth RightCamera(const SceneTruth& left) {
  SceneTruth right = left;
  right.intrinsics.fku_px += 15;
  right.intrinsics.fkv_px -= 4;
  right.intrinsics.u0_px -= 2;
  right.intrinsics.v0_px += 2;
  const Rigid3 cam_from_rig{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.2) * kDeg),
                            Eigen::Vector3d(-0.12, 0, 0)};
  right.rig_from_cam = cam_from_rig.Inverse();
  return right;
}

// Both cameras' oracle trials at one rate (so at the same instants), each camera's noise its own.
struct RigTrial {
  std::vector<std::unique_ptr<SyntheticTrial>> cameras;
  std::vector<CameraEstimate> starts;  // Each camera's DLT on [0, kStartWindowS].

  Rigid3 TrueCam1FromCam0(double t) const {
    return cameras[1]->scene.CamFromParentAt(t) * cameras[0]->scene.ParentFromCamAt(t);
  }
  std::vector<const FrameSet*> Frames() const {
    return {&cameras[0]->input.Frames(), &cameras[1]->input.Frames()};
  }
};

std::unique_ptr<RigTrial> MakeRigTrial(const SceneTruth& left, const SceneTruth& right,
                                       double rate_hz, uint64_t seed) {
  OracleOptions options;
  options.sample_rate_hz = rate_hz;
  options.noise.pixel_sigma_px = kPixelSigmaPx;
  const BoardRigScene rig = SwayingBoardRig();
  auto trial = std::make_unique<RigTrial>();
  int c = 0;
  for (const SceneTruth* scene : {&left, &right}) {
    trial->cameras.push_back(SyntheticTrial::Create(*scene, options, 1000 * seed + c, rig.layouts));
    if (trial->cameras.back() == nullptr) return nullptr;
    const MethodResult& dlt =
        trial->cameras.back()->input.Window(0.0, kStartWindowS).Prerequisite("dlt");
    EXPECT_TRUE(dlt.IsUsable()) << dlt.message;
    trial->starts.push_back(dlt.estimate);
    ++c;
  }
  return trial;
}

// The relative pose's error, true - estimated as the filter's states: [Log(R_true R_est^T) (rad),
// t_true - t_est (m)] (R_true = Exp(dtheta) R_est: the sign of the covariance's cross terms).
Eigen::Matrix<double, 6, 1> RelativePoseError(const Rigid3& est, const Rigid3& truth) {
  Eigen::Matrix<double, 6, 1> e;
  e << LogSO3(truth.rotation * est.rotation.transpose()), truth.translation - est.translation;
  return e;
}

double RelativeRotationErrorDeg(const Rigid3& est, const Rigid3& truth) {
  return LogSO3(est.rotation * truth.rotation.transpose()).norm() / kDeg;
}

// The relative rotation over time, at the start and after every update: its error and the
// filter's sd of it, sqrt(trace of its 3 x 3 covariance) (deg).
struct Trace {
  std::vector<double> times_s, rel_rot_err_deg, rel_rot_sd_deg;
};

double RotationSdDeg(const RigEkf& filter) {
  return std::sqrt(filter.CamFromCam0Covariance(1).topLeftCorner<3, 3>().trace()) / kDeg;
}

// The error of a 3-vector with covariance P exceeds 4 sqrt(trace P) with probability < 1e-3
// (chi2_3 > 16 when isotropic, less otherwise): the filter's error is within its own uncertainty.
constexpr double kSigmas = 4.0;

RigEkfOptions StaticOptions() {
  RigEkfOptions o;
  o.camera.pixel_sigma_px = kPixelSigmaPx;
  return o;
}

// Mean NEES of the relative pose (6 dof) at the end of M trials of a static rig. The filter models
// what the oracle simulates when its random walks are off (a constant truth, white Gaussian noise
// of the simulated sigma): its error is then ~N(0, P) up to linearisation, and the mean of M
// NEES lies in the two-sided 95 % band of chi2(6 M) / M (metrics/tracking.h's ChiSquareMeanBand;
// M = 40: [4.97, 7.12]; of the rotation's 3 dof alone [2.29, 3.81]). With the default random
// walks the filter is conservative on a static truth (its P holds drift that is not there: NEES
// ~ half of 6 at steady state), which is why they are off here. Camera 1's mount in the parent
// frame [Log(R_true R_hat^T), x_C error], with the covariance RigEkf::Estimate propagates to it,
// must lie in the same 6-dof band. Measured: 5.66, 2.77 and 5.31 (the test's properties).
// Mutation checked: the sign of -R_Cc dtheta_c in that propagation fails it (3.98); its
// [R_Cc t_c]x dtheta_0 term (~0.01 mm here) is below the test's resolution.
TEST(RigEkf, RelativePoseNeesInItsChiSquareBandOnOracleFrames) {
  constexpr int kTrials = 40;
  constexpr double kDurationS = 6.0, kRateHz = 10.0;
  SceneTruth left = SwayingBoardRig().scene;
  left.duration_s = kDurationS;
  const SceneTruth right = RightCamera(left);
  RigEkfOptions options = StaticOptions();
  options.camera.q_focal_px2_s = options.camera.q_center_px2_s = options.camera.q_skew_rad2_s = 0;
  options.camera.q_rotation_rad2_s = options.camera.q_position_m2_s = 0;
  options.q_rel_rotation_rad2_s = options.q_rel_translation_m2_s = 0;
  double nees_sum = 0, nees_rotation_sum = 0, nees_mount_sum = 0;
  int trials = 0;
  for (int k = 0; k < kTrials; ++k) {
    const auto trial = MakeRigTrial(left, right, kRateHz, 100 + k);
    ASSERT_NE(trial, nullptr);
    RigEkf filter;
    std::string why;
    ASSERT_TRUE(filter.Start(trial->starts, options, &why)) << why;
    RigEkfSummary summary;
    ASSERT_TRUE(RunRigEkf(trial->Frames(), kStartWindowS, &filter, {}, &summary, &why)) << why;
    ASSERT_GT(summary.updates, 0);
    const double end_s = trial->cameras[0]->input.Frames().times_s.back();
    const Eigen::Matrix<double, 6, 1> e =
        RelativePoseError(filter.CamFromCam0(1), trial->TrueCam1FromCam0(end_s));
    const Eigen::Matrix<double, 6, 6> p = filter.CamFromCam0Covariance(1);
    nees_sum += e.dot(p.ldlt().solve(e));
    const Eigen::Vector3d e_rotation = e.head<3>();
    nees_rotation_sum += e_rotation.dot(p.topLeftCorner<3, 3>().ldlt().solve(e_rotation));
    // Camera 1's estimate: its pose is the filter's relative pose composed with camera 0's (to
    // rounding), and its mount's covariance, propagated from the joint one, is as honest.
    const CameraEstimate camera0 = filter.Estimate(0), camera1 = filter.Estimate(1);
    const Rigid3 composed = camera1.cam_from_parent * camera0.parent_from_cam;
    EXPECT_LT(RotationAngleDeg(composed.rotation, filter.CamFromCam0(1).rotation), 1e-9);
    EXPECT_LT((composed.translation - filter.CamFromCam0(1).translation).norm(), 1e-12);
    const Rigid3 mount_true = trial->cameras[1]->scene.ParentFromCamAt(end_s);
    Eigen::Matrix<double, 6, 1> e_mount;
    e_mount << LogSO3(mount_true.rotation * camera1.parent_from_cam.rotation.transpose()),
        mount_true.translation - camera1.parent_from_cam.translation;
    nees_mount_sum += e_mount.dot(camera1.covariance.block<6, 6>(5, 5).ldlt().solve(e_mount));
    ++trials;
  }
  const double nees = nees_sum / trials, nees_rotation = nees_rotation_sum / trials;
  const double nees_mount = nees_mount_sum / trials;
  RecordProperty("mean_nees", std::to_string(nees));
  RecordProperty("mean_nees_rotation", std::to_string(nees_rotation));
  RecordProperty("mean_nees_camera1_mount", std::to_string(nees_mount));
  const auto [low6, high6] = ChiSquareMeanBand(trials, 6);
  const auto [low3, high3] = ChiSquareMeanBand(trials, 3);
  EXPECT_GT(nees, low6) << "mean NEES " << nees << ", band [" << low6 << ", " << high6 << "]";
  EXPECT_LT(nees, high6) << "mean NEES " << nees << ", band [" << low6 << ", " << high6 << "]";
  EXPECT_GT(nees_rotation, low3) << nees_rotation << " [" << low3 << ", " << high3 << "]";
  EXPECT_LT(nees_rotation, high3) << nees_rotation << " [" << low3 << ", " << high3 << "]";
  EXPECT_GT(nees_mount, low6) << "camera 1's mount " << nees_mount;
  EXPECT_LT(nees_mount, high6) << "camera 1's mount " << nees_mount;
}

// Runs the filter with its default random walks on a rig whose camera 1 may step, recording the
// relative rotation error after every update.
// Camera 1's start is its DLT's turned by start_offset_deg about (1, -1, 1).
Trace RunAndTrace(const SceneTruth& left, const SceneTruth& right, uint64_t seed,
                  double start_offset_deg, RigEkfSummary* summary) {
  Trace trace;
  const auto trial = MakeRigTrial(left, right, 10.0, seed);
  if (trial == nullptr) return trace;
  Rigid3& start = trial->starts[1].parent_from_cam;
  start.rotation =
      ExpSO3(Eigen::Vector3d(1, -1, 1).normalized() * start_offset_deg * kDeg) * start.rotation;
  trial->starts[1].cam_from_parent = start.Inverse();
  RigEkf filter;
  std::string why;
  EXPECT_TRUE(filter.Start(trial->starts, StaticOptions(), &why)) << why;
  trace.times_s.push_back(kStartWindowS);
  trace.rel_rot_err_deg.push_back(
      RelativeRotationErrorDeg(filter.CamFromCam0(1), trial->TrueCam1FromCam0(kStartWindowS)));
  trace.rel_rot_sd_deg.push_back(RotationSdDeg(filter));
  EXPECT_TRUE(RunRigEkf(
      trial->Frames(), kStartWindowS, &filter,
      [&](double t) {
        trace.times_s.push_back(t);
        trace.rel_rot_err_deg.push_back(
            RelativeRotationErrorDeg(filter.CamFromCam0(1), trial->TrueCam1FromCam0(t)));
        trace.rel_rot_sd_deg.push_back(RotationSdDeg(filter));
      },
      summary, &why))
      << why;
  return trace;
}

// The accuracy target of dynamic calibration on pitch and roll (spec dynamic-calibration.md; Algers
// 2018 reaches it on a loaded car), the rig metrics' re-convergence tolerance (rig.csv
// rel_rot_tol_deg).
constexpr double kTargetDeg = 0.1;

// A static rig, default random walks: the relative rotation converges. At every instant its error
// lies within kSigmas of the filter's sd, and that sd shrinks to below a quarter of the target
// (measured 0.018 deg after 8 s of updates at 10 frames/s). Camera 1's start is turned by
// kStartOffDeg (inside p0_rel_rotation_deg = 1 deg), far outside that bound: else "converged"
// would say nothing (its DLT alone is off by ~0.03 deg).
TEST(RigEkf, RelativeRotationConvergesOnAStaticRig) {
  SceneTruth left = SwayingBoardRig().scene;
  left.duration_s = 10;
  RigEkfSummary summary;
  constexpr double kStartOffDeg = 0.5;
  const Trace trace = RunAndTrace(left, RightCamera(left), 7, kStartOffDeg, &summary);
  ASSERT_GT(trace.times_s.size(), 2u);
  EXPECT_EQ(summary.skipped, 0);
  for (size_t i = 1; i < trace.times_s.size(); ++i) {
    EXPECT_LT(trace.rel_rot_err_deg[i], kSigmas * trace.rel_rot_sd_deg[i])
        << "t = " << trace.times_s[i];
  }
  EXPECT_LT(trace.rel_rot_sd_deg.back(), kTargetDeg / 4);
  EXPECT_GT(trace.rel_rot_err_deg.front(), kSigmas * trace.rel_rot_sd_deg.back());
}

// A knock of camera 1 as configs/dynamic/rig_step.yaml: its relative rotation steps by 0.3 deg
// about the rig's x axis (a pitch) at 10 s. With the default q_rel_rotation (1e-8 rad^2/s) and the
// information rate of the relative rotation here (~2e6 rad^-2/s from P: sd 0.012 deg after 8 s),
// the filter's memory sqrt(1 / (q I)) is ~7 s, but a 0.3 deg jump is ~20 sd and the first updates
// take most of it (measured: 0.12 deg left after the first update, within 0.03 deg 0.6 s after
// the step). Checked: before the step the error is within kSigmas of the sd; the step takes it out
// of the target (re-convergence is measured); it is back within the target kReconvergeS after it
// and within kSigmas of its sd at the end.
TEST(RigEkf, RelativeRotationReconvergesAfterAPitchStep) {
  constexpr double kStepAtS = 10.0, kStepDeg = 0.3, kReconvergeS = 2.0;
  SceneTruth left = SwayingBoardRig().scene;
  left.duration_s = 16;
  SceneTruth right = RightCamera(left);
  CalibrationChange knock;
  knock.from_s = knock.to_s = kStepAtS;
  knock.rpy_deg = Eigen::Vector3d(kStepDeg, 0, 0);
  right.rig_changes = {knock};
  RigEkfSummary summary;
  const Trace trace = RunAndTrace(left, right, 11, 0.0, &summary);
  ASSERT_GT(trace.times_s.size(), 2u);
  double before = 0, peak = 0, after = 0;
  for (size_t i = 1; i < trace.times_s.size(); ++i) {
    const double t = trace.times_s[i], e = trace.rel_rot_err_deg[i];
    if (t < kStepAtS) before = std::max(before, e / trace.rel_rot_sd_deg[i]);
    if (t >= kStepAtS) peak = std::max(peak, e);
    if (t >= kStepAtS + kReconvergeS) after = std::max(after, e);
  }
  EXPECT_LT(before, kSigmas);
  EXPECT_GT(peak, kTargetDeg);
  EXPECT_LT(after, kTargetDeg);
  EXPECT_LT(trace.rel_rot_err_deg.back(), kSigmas * trace.rel_rot_sd_deg.back());
}

TEST(RigEkf, OptionsAndStartsAreChecked) {
  RigEkfOptions options;
  std::string why;
  EXPECT_TRUE(options.Check(&why)) << why;
  options.q_rel_rotation_rad2_s = -1;
  EXPECT_FALSE(options.Check(&why));
  EXPECT_NE(why.find("q_rel_"), std::string::npos) << why;
  options = RigEkfOptions();
  options.p0_rel_translation_m = 0;
  EXPECT_FALSE(options.Check(&why));
  options = RigEkfOptions();
  options.camera.pixel_sigma_px = 0;
  EXPECT_FALSE(options.Check(&why));
  EXPECT_NE(why.find("pixel_sigma_px"), std::string::npos) << why;

  RigEkf filter;
  CameraEstimate one;
  one.has_camera = true;
  EXPECT_FALSE(filter.Start({one}, RigEkfOptions(), &why));
  EXPECT_NE(why.find("at least 2"), std::string::npos) << why;
  EXPECT_FALSE(filter.Start({one, CameraEstimate()}, RigEkfOptions(), &why));
  EXPECT_NE(why.find("camera 1"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
