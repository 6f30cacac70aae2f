// The adaptive estimator (adaptive/estimator.h) on the thesis simulations, built from core's
// synthetic ground truth (sim/synthetic.h) alone: convergence, the thesis's printed end points,
// the gain, the integrator's own convergence, the information form against the literal equations,
// held frames, the divergence guard and the excitation index.
#include "adaptive/estimator.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "metrics/metrics.h"
#include "sim/synthetic.h"

namespace calibench {
namespace {

// Converged noise-free runs: ||theta~|| at 240 s is ~1e-10 (rounding-limited); the bar.
constexpr double kConvergedThetaErr = 1e-6;
// Halving the integrator tolerance or step: every reported figure moves less than this, relative.
constexpr double kIntegratorRelTol = 1e-6;

// One run of the estimator on a thesis simulation, and what it recovers.
struct SimRun {
  AdaptiveSummary summary;
  DecomposedCamera camera;  // Valid when recovered.
  bool recovered = false;
  double theta_err = 0.0;
  double converge_time_s = 0.0;  // ||theta~|| < 1e-4 from then on (metrics/ThetaTrack).
};

CameraSpec TruthOf(const ThesisSimulation& sim) {
  return {sim.scene.intrinsics, sim.scene.parent_from_cam.rotation,
          sim.scene.parent_from_cam.translation, sim.scene.allow_improper_rotation};
}

AdaptiveOptions OptionsOf(const ThesisSimulation& sim) {
  AdaptiveOptions o;
  o.alpha = sim.alpha;
  return o;
}

SimRun RunSim(const ThesisSimulation& sim, const AdaptiveOptions& options) {
  std::string why;
  // Trial 0 of configs/thesis/simNN.yaml: the same noise draws.
  const auto source =
      OracleSource::Create(sim.scene, sim.measurements, TrialSeed(sim.seed, 0), &why);
  EXPECT_NE(source, nullptr) << why;
  SimRun run;
  if (!source) return run;
  const CameraSpec init = ThesisInitialGuess();
  ThetaTrack track(TruthOf(sim), ThetaTrack::Options());
  run.summary = RunAdaptiveEstimator(
      *source, ThetaFromCamera(init.intrinsics, init.ParentFromCam().Inverse()), options,
      [&](double t, const Vector16d& theta) { track.Add(t, theta); });
  run.theta_err = ThetaError(TrueTheta(TruthOf(sim)), run.summary.theta_hat);
  run.converge_time_s = track.ConvergeTimeS();
  Frame last;
  source->Measure(source->Duration(), static_cast<int>(source->Breakpoints().size()) - 2, &last);
  run.recovered = RecoverCamera(run.summary.theta_hat, last.points_in_parent, &run.camera, &why);
  return run;
}

ThesisSimulation Sim(int n) { return *MakeThesisSimulation(n); }

class ConvergedThesisSim : public ::testing::TestWithParam<int> {};

TEST_P(ConvergedThesisSim, ReachesTheTruth) {
  const ThesisSimulation sim = Sim(GetParam());
  const SimRun run = RunSim(sim, OptionsOf(sim));
  ASSERT_TRUE(run.summary.IsUsable()) << run.summary.message;
  ASSERT_TRUE(run.recovered);
  EXPECT_LT(run.theta_err, kConvergedThetaErr);
  EXPECT_NEAR(run.camera.intrinsics.fku_px, sim.scene.intrinsics.fku_px, 1e-6);
  EXPECT_NEAR(run.camera.intrinsics.phi_deg, sim.scene.intrinsics.phi_deg, 1e-8);
  EXPECT_LT((run.camera.parent_from_cam.translation - sim.scene.parent_from_cam.translation).norm(),
            1e-8);
  EXPECT_LT(
      RotationAngleDeg(run.camera.parent_from_cam.rotation, sim.scene.parent_from_cam.rotation),
      1e-8);
  EXPECT_GT(run.converge_time_s, 0.0);
  EXPECT_LT(run.converge_time_s, 240.0);
}

INSTANTIATE_TEST_SUITE_P(Thesis, ConvergedThesisSim, ::testing::Values(1, 3, 8));

// Sim 7 (5 points, small motion) does not converge; the thesis printed where it ends (f*ku 868.0,
// f*kv 875.7, u0 310.2). A faithful integration lands within 2% of them (a reference one does).
TEST(AdaptiveEstimator, Sim07EndsWhereTheThesisDid) {
  const ThesisSimulation sim = Sim(7);
  const SimRun run = RunSim(sim, OptionsOf(sim));
  ASSERT_TRUE(run.summary.IsUsable()) << run.summary.message;
  ASSERT_TRUE(run.recovered);
  EXPECT_NEAR(run.camera.intrinsics.fku_px, 868.0, 0.02 * 868.0);
  EXPECT_NEAR(run.camera.intrinsics.fkv_px, 875.7, 0.02 * 875.7);
  EXPECT_NEAR(run.camera.intrinsics.u0_px, 310.2, 0.02 * 310.2);
  EXPECT_GT(run.theta_err, 1.0);  // Really not converged.
}

TEST(AdaptiveEstimator, SmallGainConvergesMoreSlowly) {
  ThesisSimulation sim = Sim(9);  // alpha = 5.
  ASSERT_EQ(sim.alpha, 5.0);
  sim.scene.duration_s = 120;
  const SimRun slow = RunSim(sim, OptionsOf(sim));
  AdaptiveOptions fast_options = OptionsOf(sim);
  fast_options.alpha = 1000;
  const SimRun fast = RunSim(sim, fast_options);
  ASSERT_TRUE(slow.summary.IsUsable());
  ASSERT_TRUE(fast.summary.IsUsable());
  EXPECT_LT(fast.theta_err, 1e-2);  // Within 1e-2 by 120 s ...
  EXPECT_GT(slow.theta_err, 1e-2);  // ... which alpha = 5 is not.
  EXPECT_GT(slow.theta_err, 1e3 * fast.theta_err);
}

// Largest relative change between two runs' reported figures (floor 1 for values near zero).
double MaxRelativeChange(const SimRun& a, const SimRun& b) {
  const CameraIntrinsics &ka = a.camera.intrinsics, &kb = b.camera.intrinsics;
  const Eigen::Vector3d &xa = a.camera.parent_from_cam.translation,
                        &xb = b.camera.parent_from_cam.translation;
  const double pairs[][2] = {
      {ka.fku_px, kb.fku_px},
      {ka.fkv_px, kb.fkv_px},
      {ka.phi_deg, kb.phi_deg},
      {ka.u0_px, kb.u0_px},
      {ka.v0_px, kb.v0_px},
      {xa[0], xb[0]},
      {xa[1], xb[1]},
      {xa[2], xb[2]},
      {RotationAngleDeg(a.camera.parent_from_cam.rotation, b.camera.parent_from_cam.rotation), 0},
      {a.theta_err, b.theta_err}};
  double worst = 0.0;
  for (const auto& p : pairs) {
    worst = std::max(worst, std::abs(p[0] - p[1]) / std::max(1.0, std::abs(p[0])));
  }
  return worst;
}

// The integration is converged: halving its tolerance or its maximum step moves no figure by more
// than 1e-6 relative, on every thesis simulation (noisy ones: trial 0).
class IntegratorConvergence : public ::testing::TestWithParam<int> {};

TEST_P(IntegratorConvergence, HalvingToleranceOrStepChangesNoFigure) {
  const ThesisSimulation sim = Sim(GetParam());
  const SimRun base = RunSim(sim, OptionsOf(sim));
  ASSERT_TRUE(base.summary.IsUsable()) << base.summary.message;
  ASSERT_TRUE(base.recovered);
  AdaptiveOptions tighter = OptionsOf(sim);
  tighter.rtol /= 2;
  AdaptiveOptions shorter = OptionsOf(sim);
  shorter.max_step_s /= 2;
  const double rtol_change = MaxRelativeChange(base, RunSim(sim, tighter));
  const double step_change = MaxRelativeChange(base, RunSim(sim, shorter));
  EXPECT_LE(rtol_change, kIntegratorRelTol);
  EXPECT_LE(step_change, kIntegratorRelTol);
  std::printf("sim%02d: max relative change, rtol/2: %.2e, max_step/2: %.2e\n", GetParam(),
              rtol_change, step_change);
}

INSTANTIATE_TEST_SUITE_P(Thesis, IntegratorConvergence, ::testing::Range(1, 18));

// The information form integrates exactly eqs. 2.16-2.17: compare with a literal fixed-step RK4
// integration of (theta_hat, Gamma) on a non-stiff version of sim 3 (gamma0 = 1e-9, alpha = 100:
// rates ~3 /s).
TEST(AdaptiveEstimator, InformationFormMatchesLiteralGammaEquations) {
  ThesisSimulation sim = Sim(3);
  sim.scene.duration_s = 2.0;
  AdaptiveOptions options;
  options.gamma0 = 1e-9;
  options.alpha = 100.0;
  options.rtol = 1e-11;
  const auto source = OracleSource::Create(sim.scene, sim.measurements, 1, nullptr);
  ASSERT_NE(source, nullptr);
  const CameraSpec init = ThesisInitialGuess();
  const Vector16d theta0 = ThetaFromCamera(init.intrinsics, init.ParentFromCam().Inverse());
  const AdaptiveSummary ours = RunAdaptiveEstimator(*source, theta0, options);
  ASSERT_TRUE(ours.IsUsable()) << ours.message;

  // Literal equations, W_bar built row by row as the spec writes it.
  auto derivative = [&](double t, const Vector16d& theta, const Matrix16d& gamma, Vector16d* dtheta,
                        Matrix16d* dgamma) {
    Frame f;
    source->Measure(t, 0, &f);
    const int n = static_cast<int>(f.pixels.size());
    Eigen::MatrixXd w_bar = Eigen::MatrixXd::Zero(3 * n, 16);
    Eigen::VectorXd p_tilde(3 * n);
    for (int i = 0; i < n; ++i) {
      const Eigen::RowVector4d x = f.points_in_parent[i].homogeneous().transpose();
      Eigen::Matrix<double, 3, 12> w_x = Eigen::Matrix<double, 3, 12>::Zero();
      for (int r = 0; r < 3; ++r) w_x.block<1, 4>(r, 4 * r) = x;
      const Eigen::Vector3d p_hat = w_x * theta.head<12>() / (x * theta.tail<4>());
      w_bar.block<3, 12>(3 * i, 0) = w_x;
      w_bar.block<3, 4>(3 * i, 12) = -p_hat * x;
      p_tilde.segment<3>(3 * i) = f.pixels[i].homogeneous() - p_hat;
    }
    *dtheta = options.alpha * gamma * w_bar.transpose() * p_tilde;
    *dgamma = -gamma * w_bar.transpose() * w_bar * gamma;
  };
  Vector16d theta = theta0;
  Matrix16d gamma = Matrix16d::Identity() * 1e-9;
  const double h = 1e-3;
  for (int step = 0; step < 2000; ++step) {
    const double t = step * h;
    Vector16d k1, k2, k3, k4;
    Matrix16d g1, g2, g3, g4;
    derivative(t, theta, gamma, &k1, &g1);
    derivative(t + h / 2, theta + h / 2 * k1, gamma + h / 2 * g1, &k2, &g2);
    derivative(t + h / 2, theta + h / 2 * k2, gamma + h / 2 * g2, &k3, &g3);
    derivative(t + h, theta + h * k3, gamma + h * g3, &k4, &g4);
    theta += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    gamma += h / 6 * (g1 + 2 * g2 + 2 * g3 + g4);
  }
  // The estimate really moved (mostly its O(1) third-row and theta_z entries) ...
  const double moved = (theta - theta0).norm();
  EXPECT_GT(moved, 1e-2);
  // ... and both integrations agree to a millionth of that move (RK4 at h = 1e-3: ~1e-12).
  EXPECT_LT((ours.theta_hat - theta).norm(), 1e-6 * moved);
}

// Held 30 frames/s measurements (what a detector gives) converge as the continuous ones do.
TEST(AdaptiveEstimator, SampledFramesConvergeToo) {
  ThesisSimulation sim = Sim(3);
  sim.measurements.sample_rate_hz = 30;
  const SimRun run = RunSim(sim, OptionsOf(sim));
  ASSERT_TRUE(run.summary.IsUsable()) << run.summary.message;
  EXPECT_LT(run.theta_err, kConvergedThetaErr);
}

TEST(AdaptiveEstimator, DepthGuardReportsDivergenceInsteadOfCrashing) {
  const ThesisSimulation sim = Sim(3);
  const auto source = OracleSource::Create(sim.scene, sim.measurements, 1, nullptr);
  ASSERT_NE(source, nullptr);
  CameraSpec init = ThesisInitialGuess();
  init.x_c = Eigen::Vector3d(0, 100, 0);  // Every point behind the initial camera.
  const AdaptiveSummary summary = RunAdaptiveEstimator(
      *source, ThetaFromCamera(init.intrinsics, init.ParentFromCam().Inverse()), OptionsOf(sim));
  EXPECT_EQ(summary.status, MethodStatus::kDiverged);
  EXPECT_NE(summary.message.find("depth"), std::string::npos) << summary.message;
}

TEST(AdaptiveEstimator, InvalidOptionsFailCleanly) {
  const ThesisSimulation sim = Sim(3);
  const auto source = OracleSource::Create(sim.scene, sim.measurements, 1, nullptr);
  ASSERT_NE(source, nullptr);
  AdaptiveOptions bad;
  bad.alpha = -1;
  const AdaptiveSummary summary = RunAdaptiveEstimator(*source, Vector16d::Ones(), bad);
  EXPECT_EQ(summary.status, MethodStatus::kFailed);
  EXPECT_NE(summary.message.find("alpha"), std::string::npos);
}

// Richer motion excites more directions: rotation (sim 12) vs no motion at all (sim 14).
TEST(AdaptiveEstimator, ExcitationIndexRanksMotions) {
  const SimRun rotation = RunSim(Sim(12), OptionsOf(Sim(12)));
  const SimRun still = RunSim(Sim(14), OptionsOf(Sim(14)));
  const double pe_rotation =
      PersistentExcitationIndex(rotation.summary.information, rotation.summary.theta_hat);
  const double pe_still =
      PersistentExcitationIndex(still.summary.information, still.summary.theta_hat);
  EXPECT_GT(pe_rotation, 1e3 * pe_still);
  EXPECT_GE(pe_still, 0.0);
  EXPECT_LE(pe_rotation, 1.0);
}

}  // namespace
}  // namespace calibench
