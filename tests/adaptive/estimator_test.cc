#include "adaptive/estimator.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "bench/config_io.h"
#include "bench/runner.h"

namespace calibench {
namespace {

// Converged noise-free runs: ||theta~|| at 240 s is ~1e-10 (rounding-limited); the bar.
constexpr double kConvergedThetaErr = 1e-6;
// Halving the integrator tolerance or step: every reported figure moves less than this, relative.
constexpr double kIntegratorRelTol = 1e-6;

ScenarioConfig LoadThesis(const std::string& file) {
  RunConfig config;
  std::string why;
  const std::string path = std::string(CALIBENCH_SOURCE_DIR) + "/configs/thesis/" + file;
  EXPECT_TRUE(LoadRunConfig(path, &config, &why)) << why;
  EXPECT_EQ(config.scenarios.size(), 1u);
  return config.scenarios.at(0);
}

RunRow RunOnce(const ScenarioConfig& s) {
  const std::vector<RunRow> rows = RunTrial(s, 0);
  EXPECT_EQ(rows.size(), 1u);
  return rows.at(0);
}

class ConvergedThesisSim : public ::testing::TestWithParam<const char*> {};

TEST_P(ConvergedThesisSim, ReachesTheTruth) {
  const ScenarioConfig s = LoadThesis(GetParam());
  const RunRow row = RunOnce(s);
  ASSERT_EQ(row.status, "ok") << row.message;
  EXPECT_LT(row.theta_err_norm, kConvergedThetaErr);
  EXPECT_NEAR(row.fku, s.truth.intrinsics.fku_px, 1e-6);
  EXPECT_NEAR(row.phi_deg, s.truth.intrinsics.phi_deg, 1e-8);
  EXPECT_LT(row.err_xc_norm, 1e-8);
  EXPECT_LT(row.rot_err_deg, 1e-8);
  EXPECT_LT(row.rms_reproj_px, 1e-6);
  EXPECT_GT(row.converge_time_s, 0.0);
  EXPECT_LT(row.converge_time_s, 240.0);
}

INSTANTIATE_TEST_SUITE_P(Thesis, ConvergedThesisSim,
                         ::testing::Values("sim01.yaml", "sim03.yaml", "sim08.yaml"));

// Sim 7 (5 points, small motion) does not converge; the thesis printed where it ends. A faithful
// integration lands within 2% of its f*ku, f*kv and u0 (issue #2).
TEST(AdaptiveEstimator, Sim07EndsWhereTheThesisDid) {
  const ScenarioConfig s = LoadThesis("sim07.yaml");
  const RunRow row = RunOnce(s);
  ASSERT_EQ(row.status, "ok") << row.message;
  EXPECT_NEAR(row.fku, s.reference.fku_px, 0.02 * s.reference.fku_px);
  EXPECT_NEAR(row.fkv, s.reference.fkv_px, 0.02 * s.reference.fkv_px);
  EXPECT_NEAR(row.u0, s.reference.u0_px, 0.02 * s.reference.u0_px);
  EXPECT_GT(row.theta_err_norm, 1.0);  // Really not converged.
}

TEST(AdaptiveEstimator, SmallGainConvergesMoreSlowly) {
  ScenarioConfig s = LoadThesis("sim09.yaml");  // alpha = 5.
  ASSERT_EQ(s.adaptive.options.alpha, 5.0);
  s.adaptive.convergence_tol = 1e-2;
  s.duration_s = 120;
  const RunRow slow = RunOnce(s);
  s.adaptive.options.alpha = 1000;
  const RunRow fast = RunOnce(s);
  ASSERT_EQ(slow.status, "ok");
  ASSERT_EQ(fast.status, "ok");
  EXPECT_TRUE(std::isfinite(fast.converge_time_s));
  EXPECT_FALSE(std::isfinite(slow.converge_time_s));  // Never within 1e-2 in 120 s.
  EXPECT_GT(slow.theta_err_norm, 1e3 * fast.theta_err_norm);
}

// Largest relative change between two runs' reported figures (floor 1 for values near zero).
double MaxRelativeChange(const RunRow& a, const RunRow& b) {
  const double pairs[][2] = {{a.fku, b.fku},
                             {a.fkv, b.fkv},
                             {a.phi_deg, b.phi_deg},
                             {a.u0, b.u0},
                             {a.v0, b.v0},
                             {a.xc_x, b.xc_x},
                             {a.xc_y, b.xc_y},
                             {a.xc_z, b.xc_z},
                             {a.rot_err_deg, b.rot_err_deg},
                             {a.theta_err_norm, b.theta_err_norm},
                             {a.rms_reproj_px, b.rms_reproj_px}};
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
  char file[16];
  std::snprintf(file, sizeof(file), "sim%02d.yaml", GetParam());
  const ScenarioConfig s = LoadThesis(file);
  const RunRow base = RunOnce(s);
  ASSERT_EQ(base.status, "ok") << base.message;
  ScenarioConfig tighter = s;
  tighter.adaptive.options.rtol /= 2;
  ScenarioConfig shorter = s;
  shorter.adaptive.options.max_step_s /= 2;
  const double rtol_change = MaxRelativeChange(base, RunOnce(tighter));
  const double step_change = MaxRelativeChange(base, RunOnce(shorter));
  EXPECT_LE(rtol_change, kIntegratorRelTol);
  EXPECT_LE(step_change, kIntegratorRelTol);
  std::printf("%s: max relative change, rtol/2: %.2e, max_step/2: %.2e\n", file, rtol_change,
              step_change);
}

INSTANTIATE_TEST_SUITE_P(Thesis, IntegratorConvergence, ::testing::Range(1, 18));

// The information form integrates exactly eqs. 2.16-2.17: compare with a literal fixed-step RK4
// integration of (theta_hat, Gamma) on a non-stiff version of sim 3 (gamma0 = 1e-9, alpha = 100:
// rates ~3 /s).
TEST(AdaptiveEstimator, InformationFormMatchesLiteralGammaEquations) {
  ScenarioConfig s = LoadThesis("sim03.yaml");
  s.duration_s = 2.0;
  s.adaptive.options.gamma0 = 1e-9;
  s.adaptive.options.alpha = 100.0;
  s.adaptive.options.rtol = 1e-11;
  const auto source = OracleSource::Create(s.MakeScene(), s.measurements, 1, nullptr);
  ASSERT_NE(source, nullptr);
  const CameraSpec& init = s.adaptive.initial;
  const Vector16d theta0 = ThetaFromCamera(init.intrinsics, init.ParentFromCam().Inverse());
  const AdaptiveSummary ours = RunAdaptiveEstimator(*source, theta0, s.adaptive.options);
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
    *dtheta = s.adaptive.options.alpha * gamma * w_bar.transpose() * p_tilde;
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
  ScenarioConfig s = LoadThesis("sim03.yaml");
  s.measurements.sample_rate_hz = 30;
  const RunRow row = RunOnce(s);
  ASSERT_EQ(row.status, "ok") << row.message;
  EXPECT_LT(row.theta_err_norm, kConvergedThetaErr);
}

TEST(AdaptiveEstimator, DepthGuardReportsDivergenceInsteadOfCrashing) {
  ScenarioConfig s = LoadThesis("sim03.yaml");
  s.adaptive.initial.x_c = Eigen::Vector3d(0, 100, 0);  // Every point behind the initial camera.
  const RunRow row = RunOnce(s);
  EXPECT_EQ(row.status, "diverged");
  EXPECT_NE(row.message.find("depth"), std::string::npos) << row.message;
}

TEST(AdaptiveEstimator, InvalidOptionsFailCleanly) {
  const ScenarioConfig s = LoadThesis("sim03.yaml");
  const auto source = OracleSource::Create(s.MakeScene(), s.measurements, 1, nullptr);
  AdaptiveOptions bad;
  bad.alpha = -1;
  const AdaptiveSummary summary = RunAdaptiveEstimator(*source, Vector16d::Ones(), bad);
  EXPECT_EQ(summary.status, MethodStatus::kFailed);
  EXPECT_NE(summary.message.find("alpha"), std::string::npos);
}

// Richer motion excites more directions: rotation (sim 12) vs no motion at all (sim 14).
TEST(AdaptiveEstimator, ExcitationIndexRanksMotions) {
  const RunRow rotation = RunOnce(LoadThesis("sim12.yaml"));
  const RunRow still = RunOnce(LoadThesis("sim14.yaml"));
  EXPECT_GT(rotation.pe_min_eig, 1e3 * still.pe_min_eig);
  EXPECT_GE(still.pe_min_eig, 0.0);
  EXPECT_LE(rotation.pe_min_eig, 1.0);
}

}  // namespace
}  // namespace calibench
