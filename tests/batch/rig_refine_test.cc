#include "batch/rig_refine.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>

#include "batch/rig_reprojection_error.h"
#include "sim/example_rigs.h"
#include "sim/rig_frames.h"

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;
// Noise-free data: the solve stops at ~1e-10 relative (RefineCalibration's tolerances); the bar is
// the brief's 1e-6 (relative for intrinsics, degrees and metres for poses).
constexpr double kNoiseFreeRel = 1e-6;
// Analytic against ceres::Jet: one expression in two evaluation orders differs by rounding only.
constexpr double kJacobianRel = 1e-9;

RigRefineOptions OptionsFor(const CameraRig& rig) {
  RigRefineOptions o;
  for (const RigCamera& camera : rig.cameras) o.models.push_back(camera.lens_model);
  return o;
}

SyntheticRigFrames Frames(const CameraRig& rig, int num_frames, uint64_t seed,
                          double sigma_px = 0.0) {
  RigFramesOptions o;
  o.num_frames = num_frames;
  o.pixel_sigma_px = sigma_px;
  Rng rng(seed);
  return MakeRigFrames(rig, o, &rng);
}

// A start as a rough per-camera calibration leaves it: 2 % on focal lengths, pixels off on the
// principal point, distortion off, 0.5 deg and 5 mm off on every pose.
void Perturb(CameraRig* rig, std::vector<Rigid3>* rig_from_board) {
  for (size_t c = 0; c < rig->cameras.size(); ++c) {
    CameraIntrinsics& k = rig->cameras[c].intrinsics;
    k.fku_px *= 1.02, k.fkv_px *= 0.985, k.u0_px += 3, k.v0_px -= 2;
    if (k.family == LensFamily::kRadTan) k.k1 += 0.02, k.k2 -= 0.01;
    if (k.family == LensFamily::kDoubleSphere) k.xi += 0.03, k.alpha -= 0.02;
    if (c == 0) continue;
    Rigid3& pose = rig->cameras[c].cam_from_rig;
    pose.rotation = ExpSO3(Eigen::Vector3d(0.3, -0.4, 0.2) * kDeg) * pose.rotation;
    pose.translation += Eigen::Vector3d(0.005, -0.003, 0.004);
  }
  for (Rigid3& pose : *rig_from_board) {
    pose.rotation = ExpSO3(Eigen::Vector3d(-0.2, 0.3, 0.4) * kDeg) * pose.rotation;
    pose.translation += Eigen::Vector3d(-0.004, 0.005, 0.003);
  }
}

void ExpectRigRecovered(const CameraRig& got, const CameraRig& truth, double rel) {
  for (int c = 0; c < truth.NumCameras(); ++c) {
    const std::array<double, 10> a = got.cameras[c].intrinsics.Params();
    const std::array<double, 10> b = truth.cameras[c].intrinsics.Params();
    for (int i = 0; i < 10; ++i) {
      EXPECT_NEAR(a[i], b[i], rel * std::max(1.0, std::abs(b[i])))
          << "camera " << c << " " << ParamNames(truth.cameras[c].intrinsics.family)[i];
    }
    EXPECT_LT(RotationAngleDeg(got.cameras[c].cam_from_rig.rotation,
                               truth.cameras[c].cam_from_rig.rotation),
              rel)
        << "camera " << c;
    EXPECT_LT((got.cameras[c].cam_from_rig.translation - truth.cameras[c].cam_from_rig.translation)
                  .norm(),
              rel)
        << "camera " << c;
  }
}

TEST(RigRefine, OptionsCheck) {
  RigRefineOptions o;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("models"), std::string::npos);
  o.models = {LensModel::kPinhole, LensModel::kPinhole};
  EXPECT_TRUE(o.Check(&why));
  o.loss_scale_px = 0;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("loss_scale_px"), std::string::npos);
}

// RigViewCostFunction's hand-written Jacobians against RigReprojectionError's ceres::Jet, for a
// radtan and a double-sphere camera, at a rig pose and a frame pose away from the identity.
TEST(RigRefine, AnalyticJacobiansMatchJets) {
  const CameraRig rig = ExampleMixedThreeCameraRig();
  const Rigid3 rig_from_board = {ExpSO3(Eigen::Vector3d(0.2, 0.5, -0.1)),
                                 Eigen::Vector3d(0.3, -0.1, 0.6)};
  const std::vector<Eigen::Vector3d> points = {
      {0.0, 0.0, 0.0}, {0.12, 0.04, 0.0}, {0.2, 0.16, 0.0}};
  for (int c : {0, 1}) {
    const IntrinsicsArray intrinsics = rig.cameras[c].intrinsics.Params();
    const Eigen::Quaterniond qc(rig.cameras[c].cam_from_rig.rotation);
    const Eigen::Quaterniond qf(rig_from_board.rotation);
    const double cam_q[4] = {qc.x(), qc.y(), qc.z(), qc.w()};
    const double board_q[4] = {qf.x(), qf.y(), qf.z(), qf.w()};
    const Eigen::Vector3d& tc = rig.cameras[c].cam_from_rig.translation;
    const double* params[5] = {intrinsics.data(), cam_q, tc.data(), board_q,
                               rig_from_board.translation.data()};
    const LensFamily family = rig.cameras[c].intrinsics.family;
    for (const Eigen::Vector3d& point : points) {
      const Eigen::Vector2d pixel(300, 200);
      std::unique_ptr<ceres::CostFunction> jet(RigReprojectionError::Create(pixel, point, family));
      RigViewCostFunction analytic({point}, {pixel}, family);
      constexpr int kSizes[5] = {10, 4, 3, 4, 3};
      std::array<std::vector<double>, 5> ja, jb;
      double* pa[5];
      double* pb[5];
      for (int b = 0; b < 5; ++b) {
        ja[b].resize(2 * kSizes[b]), jb[b].resize(2 * kSizes[b]);
        pa[b] = ja[b].data(), pb[b] = jb[b].data();
      }
      double ra[2], rb[2];
      ASSERT_TRUE(jet->Evaluate(params, ra, pa));
      ASSERT_TRUE(analytic.Evaluate(params, rb, pb));
      for (int r = 0; r < 2; ++r) EXPECT_NEAR(ra[r], rb[r], kJacobianRel * std::abs(ra[r]) + 1e-9);
      for (int b = 0; b < 5; ++b) {
        double scale = 1.0;
        for (double v : ja[b]) scale = std::max(scale, std::abs(v));
        for (size_t k = 0; k < ja[b].size(); ++k) {
          EXPECT_NEAR(ja[b][k], jb[b][k], kJacobianRel * scale)
              << "camera " << c << " block " << b << " entry " << k;
        }
      }
    }
  }
}

TEST(RigRefine, StereoRigFromExactFrames) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 16, 21);
  ASSERT_EQ(s.frames.size(), 16u);
  CameraRig start = truth;
  std::vector<Rigid3> start_poses = s.rig_from_board;
  Perturb(&start, &start_poses);
  const RigRefineResult result = RefineRig(s.frames, start, start_poses, OptionsFor(truth));
  ASSERT_TRUE(result.IsUsable()) << result.message;
  ExpectRigRecovered(result.rig, truth, kNoiseFreeRel);
  EXPECT_LT(result.rms_reproj_px, 1e-6);
  EXPECT_EQ(result.num_points, [&] {
    int n = 0;
    for (const RigFrame& f : s.frames)
      for (const View& v : f.views_by_camera) n += static_cast<int>(v.points.size());
    return n;
  }());
  ASSERT_EQ(result.frame_rms_px.size(), s.frames.size());
  ASSERT_EQ(result.camera_rms_px.size(), 2u);
  // Epipolar errors of the recovered rig on its own exact corners: rounding only.
  const EpipolarErrors epipolar = ComputeEpipolarErrors(s.frames, result.rig, 0, 1);
  EXPECT_GT(epipolar.num_points, 0);
  EXPECT_LT(epipolar.rms_px, 1e-6);
}

TEST(RigRefine, TriRigWithDoubleSphereFromExactFrames) {
  const CameraRig truth = ExampleMixedThreeCameraRig();
  const SyntheticRigFrames s = Frames(truth, 30, 22);
  ASSERT_EQ(s.frames.size(), 30u);
  CameraRig start = truth;
  std::vector<Rigid3> start_poses = s.rig_from_board;
  Perturb(&start, &start_poses);
  const RigRefineResult result = RefineRig(s.frames, start, start_poses, OptionsFor(truth));
  ASSERT_TRUE(result.IsUsable()) << result.message;
  ExpectRigRecovered(result.rig, truth, kNoiseFreeRel);
  // Camera 2 never shares a frame with camera 0 (sim/rig_frames.h): its frames are NaN there.
  for (size_t f = 0; f < s.frames.size(); ++f) {
    EXPECT_FALSE(!std::isnan(result.frame_rms_px[f][0]) && !std::isnan(result.frame_rms_px[f][2]));
  }
}

// Every intrinsic fixed: only the extrinsics and the frame poses move, and the pose of camera 1
// is still recovered.
TEST(RigRefine, FixedIntrinsicsMoveOnlyThePoses) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 10, 23);
  CameraRig start = truth;
  std::vector<Rigid3> start_poses = s.rig_from_board;
  Perturb(&start, &start_poses);
  for (int c = 0; c < 2; ++c) start.cameras[c].intrinsics = truth.cameras[c].intrinsics;
  RigRefineOptions o = OptionsFor(truth);
  o.fix_intrinsics = true;
  const RigRefineResult result = RefineRig(s.frames, start, start_poses, o);
  ASSERT_TRUE(result.IsUsable()) << result.message;
  ExpectRigRecovered(result.rig, truth, kNoiseFreeRel);
  EXPECT_TRUE(std::isnan(result.intrinsics_std[0][0]));
  EXPECT_GT(result.pose_uncertainty[1].baseline_std_mm, 0.0);
}

// A given rig evaluated on new frames: intrinsics and extrinsics held, only the frame poses move;
// nothing of the rig has a covariance.
TEST(RigRefine, FixedRigMovesOnlyTheFramePoses) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 8, 26);
  CameraRig start = truth;
  std::vector<Rigid3> start_poses = s.rig_from_board;
  Perturb(&start, &start_poses);
  start = truth;  // Only the frame poses are off.
  RigRefineOptions o = OptionsFor(truth);
  o.fix_intrinsics = o.fix_extrinsics = true;
  const RigRefineResult result = RefineRig(s.frames, start, start_poses, o);
  ASSERT_TRUE(result.IsUsable()) << result.message;
  EXPECT_EQ(result.rig.cameras[1].cam_from_rig, truth.cameras[1].cam_from_rig);
  EXPECT_EQ(result.rig.cameras[1].intrinsics, truth.cameras[1].intrinsics);
  EXPECT_LT(result.rms_reproj_px, 1e-6);
  for (size_t f = 0; f < s.frames.size(); ++f) {
    EXPECT_LT(RotationAngleDeg(result.rig_from_board[f].rotation, s.rig_from_board[f].rotation),
              kNoiseFreeRel);
  }
  EXPECT_EQ(result.pose_uncertainty[1].baseline_std_mm, 0.0);
  EXPECT_TRUE(std::isnan(result.intrinsics_std[1][0]));
}

// One corner 50 px off in one view: the Huber loss (1 px) caps its pull at that of a 1 px
// residual among ~1500 corners and keeps the baseline within kHuberShareOfStd of its std from
// the clean solve's (measured 0.012), where plain least squares is pulled by ~1 std.
constexpr double kHuberShareOfStd = 0.05;
TEST(RigRefine, HuberLossResistsAnOutlierCorner) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 16, 27, 0.3);
  RigRefineOptions o = OptionsFor(truth);
  const RigRefineResult clean = RefineRig(s.frames, truth, s.rig_from_board, o);
  ASSERT_TRUE(clean.IsUsable()) << clean.message;
  std::vector<RigFrame> frames = s.frames;
  for (RigFrame& frame : frames) {
    if (frame.views_by_camera[1].points.empty()) continue;
    frame.views_by_camera[1].pixels[5] += Eigen::Vector2d(40, -30);
    break;
  }
  const RigRefineResult plain = RefineRig(frames, truth, s.rig_from_board, o);
  o.loss = RobustLoss::kHuber;
  const RigRefineResult huber = RefineRig(frames, truth, s.rig_from_board, o);
  ASSERT_TRUE(plain.IsUsable() && huber.IsUsable()) << plain.message << huber.message;
  const double std_mm = clean.pose_uncertainty[1].baseline_std_mm;
  const double plain_off = std::abs(plain.rig.BaselineM(1) - clean.rig.BaselineM(1)) * 1000;
  const double huber_off = std::abs(huber.rig.BaselineM(1) - clean.rig.BaselineM(1)) * 1000;
  EXPECT_LT(huber_off, kHuberShareOfStd * std_mm);
  std::printf("baseline off the clean solve: huber %.4f mm, plain %.4f mm (std %.4f mm)\n",
              huber_off, plain_off, std_mm);
  EXPECT_LT(huber_off, plain_off);
}

// The epipolar error checks the rig alone. Through the true rig on noisy corners, a corner's
// distance from the other's epipolar line carries its own noise across the line and the other
// pixel's through the line: std sqrt(2) sigma, the same in both images (nearly the same
// distance), so their mean too; the lens scales it locally (angle times fku against pixels,
// k1 ~ -0.2 at the edges): within 30 %. A rig turned by 0.2 deg about camera 1's x axis (1.8 px
// at f = 505 px) stands out above it.
constexpr double kEpipolarLow = 0.7, kEpipolarHigh = 1.3;  // Times sqrt(2) sigma.
TEST(RigRefine, EpipolarErrorsSeeAWrongRig) {
  const CameraRig truth = ExampleStereoRig();
  constexpr double kSigmaPx = 0.5;
  const SyntheticRigFrames s = Frames(truth, 12, 28, kSigmaPx);
  const EpipolarErrors good = ComputeEpipolarErrors(s.frames, truth, 0, 1);
  ASSERT_GT(good.num_points, 100);
  EXPECT_GT(good.rms_px, kEpipolarLow * std::sqrt(2.0) * kSigmaPx);
  EXPECT_LT(good.rms_px, kEpipolarHigh * std::sqrt(2.0) * kSigmaPx);
  CameraRig turned = truth;
  turned.cameras[1].cam_from_rig.rotation =
      ExpSO3(Eigen::Vector3d(0.2 * kDeg, 0, 0)) * turned.cameras[1].cam_from_rig.rotation;
  const EpipolarErrors bad = ComputeEpipolarErrors(s.frames, turned, 0, 1);
  EXPECT_GT(bad.rms_px, 2 * good.rms_px);
  std::printf("epipolar RMS: true rig %.3f px, turned by 0.2 deg %.3f px\n", good.rms_px,
              bad.rms_px);
  EXPECT_EQ(ComputeEpipolarErrors(s.frames, truth, 0, 5).num_points, 0);  // No such camera.
}

// A frame pose that puts the board behind camera 1 at the start: Ceres cannot evaluate it, and
// the message names the frame and the camera.
TEST(RigRefine, FailureNamesTheViewThatCannotProject) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 6, 29);
  std::vector<Rigid3> start = s.rig_from_board;
  int bad = -1;
  for (size_t f = 0; f < s.frames.size() && bad < 0; ++f) {
    if (!s.frames[f].views_by_camera[1].points.empty()) bad = static_cast<int>(f);
  }
  ASSERT_GE(bad, 0);
  start[bad].translation.z() = -start[bad].translation.z();  // Behind both cameras.
  const RigRefineResult result = RefineRig(s.frames, truth, start, OptionsFor(truth));
  ASSERT_FALSE(result.IsUsable());
  EXPECT_NE(result.message.find("Traced to frame " + s.frames[bad].name + ", cam0"),
            std::string::npos)
      << result.message;
}

// Camera 1 of the three-camera rig removed from every frame: camera 2 shares no frame with
// camera 0 any more, and the refinement says so instead of a rank-deficient covariance.
TEST(RigRefine, RefusesACameraCutOffFromCameraZero) {
  const CameraRig truth = ExampleMixedThreeCameraRig();
  SyntheticRigFrames s = Frames(truth, 20, 30);
  for (RigFrame& frame : s.frames) frame.views_by_camera[1] = View();
  const RigRefineResult result = RefineRig(s.frames, truth, s.rig_from_board, OptionsFor(truth));
  EXPECT_FALSE(result.IsUsable());
  EXPECT_NE(result.message.find("cam1 sees the target in no frame"), std::string::npos)
      << result.message;
  // With camera 1 kept only in frames of its own, camera 2 is cut off.
  s = Frames(truth, 20, 30);
  for (RigFrame& frame : s.frames) {
    if (!frame.views_by_camera[0].points.empty()) frame.views_by_camera[1] = View();
  }
  const RigRefineResult cut = RefineRig(s.frames, truth, s.rig_from_board, OptionsFor(truth));
  EXPECT_FALSE(cut.IsUsable());
  EXPECT_NE(cut.message.find("no frame links cam1, cam2 to cam0"), std::string::npos)
      << cut.message;
}

TEST(RigRefine, RefusesACameraThatSeesNothing) {
  const CameraRig truth = ExampleStereoRig();
  SyntheticRigFrames s = Frames(truth, 6, 24);
  for (RigFrame& frame : s.frames) frame.views_by_camera[1] = View();
  const RigRefineResult result = RefineRig(s.frames, truth, s.rig_from_board, OptionsFor(truth));
  EXPECT_FALSE(result.IsUsable());
  EXPECT_NE(result.message.find("cam1 sees the target in no frame"), std::string::npos)
      << result.message;
}

TEST(RigRefine, BoundNeedsTheModelsFamily) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 6, 25);
  RigRefineOptions o = OptionsFor(truth);
  o.models[1] = LensModel::kPinholeEqui;
  RigRefineResult bound;
  std::string why;
  EXPECT_FALSE(RigCovarianceAt(s.frames, truth, s.rig_from_board, o, 0.5, &bound, &why));
  EXPECT_NE(why.find("cam1"), std::string::npos) << why;
}

// Monte Carlo against the Cramer-Rao bound: one geometry (24 frames of the stereo rig), kTrials
// noise draws of sigma = 0.5 px, each refined from the truth (RunMonteCarlo). The sample RMSE of an
// efficient unbiased estimator over T trials is the CRLB times sqrt(chi^2_T / T): for T = 80 its
// relative standard deviation is 1 / sqrt(2T) = 0.079, so [0.75, 1.3] is 3.2 (below) and 3.8
// (above) such deviations wide, room for the figures tested at once (4 per camera, and each fku)
// and a small nonlinear bias.
constexpr int kTrials = 80;
constexpr double kRatioLow = 0.75, kRatioHigh = 1.3;
// The reported std uses sigma_hat (relative std 1 / sqrt(2 (m - p)) ~ 1 % at m ~ 5000 residuals)
// and the Jacobian at the estimate, not at the truth: within 5 % of the bound.
constexpr double kReportedStdRel = 0.05;

// The Monte Carlo of one geometry: kTrials noise draws on `exact`, each refined from the truth;
// per camera c >= 1 the RMSE of the relative rotation vector (deg, per axis) and of the baseline
// (mm), and of every camera's fku (px), with the bound at the truth and the first trial's
// reported std.
struct MonteCarloOutcome {
  RigRefineResult bound, first;
  std::vector<Eigen::Vector3d> rotation_rmse_deg;
  std::vector<double> baseline_rmse_mm, fku_rmse_px;
  std::vector<double> direction_rmse_deg;  // The angle of c / |c| from the truth's, RMS.
};
MonteCarloOutcome RunMonteCarlo(const CameraRig& truth, const SyntheticRigFrames& exact,
                                double sigma_px, uint64_t seed) {
  const int n = truth.NumCameras();
  const RigRefineOptions options = OptionsFor(truth);
  MonteCarloOutcome out;
  std::string why;
  EXPECT_TRUE(RigCovarianceAt(exact.frames, truth, exact.rig_from_board, options, sigma_px,
                              &out.bound, &why))
      << why;
  std::vector<Eigen::Vector3d> sq_r(n, Eigen::Vector3d::Zero());
  std::vector<double> sq_b(n, 0.0), sq_f(n, 0.0), sq_u(n, 0.0);
  Rng noise(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<RigFrame> frames = exact.frames;
    for (RigFrame& frame : frames) {
      for (View& view : frame.views_by_camera) {
        for (Eigen::Vector2d& p : view.pixels) {
          p += sigma_px * NormalPair<Eigen::Vector2d>(&noise);
        }
      }
    }
    const RigRefineResult r = RefineRig(frames, truth, exact.rig_from_board, options);
    EXPECT_TRUE(r.IsUsable()) << r.message;
    if (!r.IsUsable()) return out;
    if (trial == 0) out.first = r;
    for (int c = 0; c < n; ++c) {
      const double df = r.rig.cameras[c].intrinsics.fku_px - truth.cameras[c].intrinsics.fku_px;
      sq_f[c] += df * df;
      if (c == 0) continue;
      sq_r[c] += (r.rig.RelativeRotationDeg(c) - truth.RelativeRotationDeg(c)).cwiseAbs2();
      const double db = 1000 * (r.rig.BaselineM(c) - truth.BaselineM(c));
      sq_b[c] += db * db;
      const Eigen::Vector3d u = r.rig.CentreInRig(c).normalized();
      const Eigen::Vector3d u_true = truth.CentreInRig(c).normalized();
      const double angle_deg = std::atan2(u.cross(u_true).norm(), u.dot(u_true)) * 180.0 / M_PI;
      sq_u[c] += angle_deg * angle_deg;
    }
  }
  for (int c = 0; c < n; ++c) {
    out.rotation_rmse_deg.push_back((sq_r[c] / kTrials).cwiseSqrt());
    out.baseline_rmse_mm.push_back(std::sqrt(sq_b[c] / kTrials));
    out.fku_rmse_px.push_back(std::sqrt(sq_f[c] / kTrials));
    out.direction_rmse_deg.push_back(std::sqrt(sq_u[c] / kTrials));
  }
  return out;
}

void ExpectEfficient(const MonteCarloOutcome& mc, const CameraRig& truth, double sigma_px) {
  ASSERT_EQ(static_cast<int>(mc.fku_rmse_px.size()), truth.NumCameras());
  for (int c = 0; c < truth.NumCameras(); ++c) {
    const double fku_ratio = mc.fku_rmse_px[c] / mc.bound.intrinsics_std[c][0];
    EXPECT_GT(fku_ratio, kRatioLow) << "camera " << c;
    EXPECT_LT(fku_ratio, kRatioHigh) << "camera " << c;
    EXPECT_NEAR(mc.first.intrinsics_std[c][0], mc.bound.intrinsics_std[c][0],
                kReportedStdRel * mc.bound.intrinsics_std[c][0]);
    std::printf("camera %d fku: RMSE / CRLB = %.3f (CRLB %.4f px)\n", c, fku_ratio,
                mc.bound.intrinsics_std[c][0]);
    if (c == 0) continue;
    const RigPoseUncertainty& crlb = mc.bound.pose_uncertainty[c];
    const RigPoseUncertainty& reported = mc.first.pose_uncertainty[c];
    for (int k = 0; k < 3; ++k) {
      const double ratio = mc.rotation_rmse_deg[c][k] / crlb.rotation_std_deg[k];
      EXPECT_GT(ratio, kRatioLow) << "camera " << c << " axis " << k;
      EXPECT_LT(ratio, kRatioHigh) << "camera " << c << " axis " << k;
      EXPECT_NEAR(reported.rotation_std_deg[k], crlb.rotation_std_deg[k],
                  kReportedStdRel * crlb.rotation_std_deg[k]);
      std::printf("camera %d rotation axis %d: RMSE / CRLB = %.3f (CRLB %.4f deg, reported %.4f)\n",
                  c, k, ratio, crlb.rotation_std_deg[k], reported.rotation_std_deg[k]);
    }
    const double ratio = mc.baseline_rmse_mm[c] / crlb.baseline_std_mm;
    EXPECT_GT(ratio, kRatioLow) << "camera " << c;
    EXPECT_LT(ratio, kRatioHigh) << "camera " << c;
    EXPECT_NEAR(reported.baseline_std_mm, crlb.baseline_std_mm,
                kReportedStdRel * crlb.baseline_std_mm);
    // The direction's RMS angle (2 dof: its square is a sum of two squares) against the bound.
    const double direction_ratio = mc.direction_rmse_deg[c] / crlb.baseline_direction_std_deg;
    EXPECT_GT(direction_ratio, kRatioLow) << "camera " << c;
    EXPECT_LT(direction_ratio, kRatioHigh) << "camera " << c;
    EXPECT_NEAR(reported.baseline_direction_std_deg, crlb.baseline_direction_std_deg,
                kReportedStdRel * crlb.baseline_direction_std_deg);
    std::printf(
        "camera %d baseline: RMSE / CRLB = %.3f (CRLB %.4f mm, reported %.4f); direction "
        "RMSE / CRLB = %.3f (CRLB %.4f deg)\n",
        c, ratio, crlb.baseline_std_mm, reported.baseline_std_mm, direction_ratio,
        crlb.baseline_direction_std_deg);
  }
  EXPECT_NEAR(mc.first.sigma_hat_px, sigma_px, kReportedStdRel * sigma_px);
}

TEST(RigRefine, MonteCarloMatchesTheCramerRaoBound) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames exact = Frames(truth, 24, 31);
  ASSERT_EQ(exact.frames.size(), 24u);
  constexpr double kSigmaPx = 0.5;
  ExpectEfficient(RunMonteCarlo(truth, exact, kSigmaPx, 99), truth, kSigmaPx);
}

// The same on the three-camera rig: camera 2 (pinhole) shares frames with the double-sphere
// camera 1 only, so its pose is known through camera 1's; the bound counts that chain.
TEST(RigRefine, MonteCarloMatchesTheCramerRaoBoundThroughALink) {
  const CameraRig truth = ExampleMixedThreeCameraRig();
  const SyntheticRigFrames exact = Frames(truth, 30, 32);
  ASSERT_EQ(exact.frames.size(), 30u);
  constexpr double kSigmaPx = 0.5;
  ExpectEfficient(RunMonteCarlo(truth, exact, kSigmaPx, 98), truth, kSigmaPx);
}

}  // namespace
}  // namespace calibench
