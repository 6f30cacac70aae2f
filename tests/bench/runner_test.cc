#include "bench/run/runner.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "bench/config/config_io.h"
#include "bench/run/csv.h"
#include "bench/run/stats.h"
#include "bench/run/table.h"
#include "tests/common/scenario_yaml.h"

namespace calibench {
namespace {

TEST(Stats, QuantilesMatchNumpyLinearInterpolation) {
  // numpy.quantile([3, 1, 4, 1, 5, 9, 2, 6], [0.025, 0.5, 0.975]) = [1.0, 3.5, 8.475]
  const std::vector<double> v = {3, 1, 4, 1, 5, 9, 2, 6, std::nan("")};
  EXPECT_DOUBLE_EQ(Quantile(v, 0.025), 1.0);
  EXPECT_DOUBLE_EQ(Median(v), 3.5);
  EXPECT_NEAR(Quantile(v, 0.975), 8.475, 1e-12);
  EXPECT_TRUE(std::isnan(Median({std::nan("")})));
}

TEST(Csv, QuotesFieldsThatNeedIt) {
  EXPECT_EQ(CsvLine({"a", "b,c", "say \"hi\"", "1.5"}), "a,\"b,c\",\"say \"\"hi\"\"\",1.5\n");
}

ScenarioConfig NoisyShortScenario() {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfig(std::string(CALIBENCH_SOURCE_DIR) + "/tests/fixtures/thesis/sim17.yaml",
                            &config, &why))
      << why;
  ScenarioConfig s = config.scenarios.at(0);
  s.duration_s = 20;
  s.trials = 6;
  return s;
}

// Every number derives from (seed, trial): the rows are identical for 1 and 2 threads.
TEST(Runner, RowsDoNotDependOnTheThreadCount) {
  const std::vector<ScenarioConfig> scenarios = {NoisyShortScenario()};
  RunOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const std::vector<RunRow> a = RunScenarios(scenarios, one), b = RunScenarios(scenarios, two);
  ASSERT_EQ(a.size(), 6u);
  ASSERT_EQ(b.size(), 6u);
  for (size_t i = 0; i < a.size(); ++i) {
    // Every runs.csv column (timings live in timings.csv).
    EXPECT_EQ(RunRowFields(a[i]), RunRowFields(b[i])) << "row " << i;
  }
  EXPECT_NE(a[0].fku_px, a[1].fku_px);  // Trials really draw different noise.
}

ScenarioConfig LoadOne(const std::string& relative) {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfig(std::string(CALIBENCH_SOURCE_DIR) + "/" + relative, &config, &why))
      << why;
  return config.scenarios.at(0);
}

// Noise-free thesis sim 3: adaptive, dlt and ceres all recover the truth (1e-6 relative).
TEST(Runner, AllMethodsRecoverTheTruthOnNoiseFreeData) {
  ScenarioConfig s = LoadOne("tests/fixtures/thesis/sim03.yaml");
  EnableOnly(&s, {"adaptive", "dlt", "ceres"});
  const std::vector<RunRow> rows = RunTrial(s, 0);
  ASSERT_EQ(rows.size(), 3u);
  for (const RunRow& r : rows) {
    ASSERT_EQ(r.status, "ok") << r.method << ": " << r.message;
    EXPECT_LT(std::abs(r.err_fku_px) / 822, 1e-6) << r.method;
    EXPECT_LT(std::abs(r.err_fkv_px) / 813, 1e-6) << r.method;
    EXPECT_LT(std::abs(r.err_phi_deg) / 87, 1e-6) << r.method;
    EXPECT_LT(std::abs(r.err_u0_px) / 321, 1e-6) << r.method;
    EXPECT_LT(std::abs(r.err_v0_px) / 239, 1e-6) << r.method;
    EXPECT_LT(r.xc_err_m, 1e-6) << r.method;
    EXPECT_LT(r.theta_err_norm, 1e-6) << r.method;
  }
  EXPECT_EQ(rows[1].method, "dlt");
  EXPECT_EQ(rows[2].method, "ceres");
}

// A method's declared outputs reach its row (adaptive's pe_min_eig; none for the others: NaN) and
// come back from runs.csv's fields (what resume and merge read).
TEST(Runner, MethodOutputsAreWrittenAndReadBack) {
  ScenarioConfig s = LoadOne("tests/fixtures/thesis/sim03.yaml");
  EnableOnly(&s, {"adaptive", "dlt"});
  const std::vector<RunRow> rows = RunTrial(s, 0);
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(rows[0].status, "ok") << rows[0].message;
  // Thesis sim 3 is excited (>= 5.2e-5: methods/adaptive.cc, kMinIdentifiablePeIndex) and the
  // index is a ratio of eigenvalues (<= 1).
  ASSERT_EQ(rows[0].method_outputs.count("pe_min_eig"), 1u);
  EXPECT_GT(rows[0].method_outputs.at("pe_min_eig"), 5e-5);
  EXPECT_LE(rows[0].method_outputs.at("pe_min_eig"), 1.0);
  EXPECT_TRUE(rows[1].method_outputs.empty());
  const std::vector<std::string>& header = RunRowHeader();
  const size_t pe = std::find(header.begin(), header.end(), "pe_min_eig") - header.begin();
  ASSERT_LT(pe, header.size());
  EXPECT_EQ(RunRowFields(rows[1])[pe], "nan");
  for (const RunRow& r : rows) {
    RunRow back;
    std::string why;
    ASSERT_TRUE(ParseRunRow(header, RunRowFields(r), &back, &why)) << why;
    // runs.csv's text (FormatNumber: 10 significant digits) reads back to itself.
    EXPECT_EQ(RunRowFields(back), RunRowFields(r)) << r.method;
    ASSERT_EQ(back.method_outputs.size(), r.method_outputs.size()) << r.method;
    for (const auto& [name, value] : r.method_outputs) {
      EXPECT_NEAR(back.method_outputs.at(name), value, 1e-9 * std::abs(value)) << name;
    }
  }
}

// With pixel noise, ceres reports standard deviations and the CRLB is filled in; they agree.
TEST(Runner, CeresRowsCarryStdAndCrlb) {
  ScenarioConfig s = LoadOne("tests/fixtures/crlb50.yaml");
  s.trials = 1;
  s.FindMethod("adaptive")->enabled = false;
  const std::vector<RunRow> rows = RunTrial(s, 0);
  ASSERT_EQ(rows.size(), 2u);
  const RunRow& ceres = rows[1];
  ASSERT_EQ(ceres.status, "ok") << ceres.message;
  EXPECT_GT(ceres.crlb_fku_px, 0.0);
  // Std at the estimate vs CRLB at the truth, sigma estimated vs known: within 20%.
  EXPECT_NEAR(ceres.std_fku_px / ceres.crlb_fku_px, 1.0, 0.2);
  EXPECT_NEAR(ceres.std_u0_px / ceres.crlb_u0_px, 1.0, 0.2);
  EXPECT_TRUE(std::isnan(rows[0].std_fku_px));  // dlt reports no covariance.
}

// A two-board rig, noise-free: zhang (both extrinsic estimates), dlt and ceres recover the truth,
// for the moving camera (eye-in-hand) and the fixed camera (eye-to-hand) alike.
class RigRecovery : public ::testing::TestWithParam<CalibrationCase> {};

TEST_P(RigRecovery, EveryBatchMethodRecoversTheTruth) {
  ScenarioConfig s = LoadOne("tests/fixtures/rig_moving.yaml");
  s.trials = 1;
  s.measurements.noise = NoiseOptions();
  s.FindMethod("adaptive")->enabled = false;
  SetMethodOption(&s, "zhang", "model", "pinhole");
  SetMethodOption(&s, "zhang_handeye", "model", "pinhole");
  if (GetParam() == CalibrationCase::kFixedCamera) {
    // The same relative geometry seen the other way round: boards on the body, camera in W.
    s.calibration_case = CalibrationCase::kFixedCamera;
    s.motion.frame = TwistProfile::Frame::kWorld;
  }
  const std::vector<RunRow> rows = RunTrial(s, 0);
  ASSERT_EQ(rows.size(), 4u);
  for (const RunRow& r : rows) {
    ASSERT_EQ(r.status, "ok") << r.method << ": " << r.message;
    // Intrinsics: 1e-6 relative, the bar. Extrinsic: dlt and ceres work in double
    // (1e-6); cv::calibrateCamera takes float32 points (~1e-7 relative, 4e-5 px here), which
    // leaves ~1e-5 deg in its per-view poses and in both extrinsic estimates (measured <= 1.2e-5
    // deg: averaging and hand-eye alike; Tsai's own rotation step, singular at this half-turn
    // mount, needed 2e-4).
    const bool float32 = r.method.rfind("zhang", 0) == 0;
    EXPECT_LT(std::abs(r.err_fku_px) / 822, 1e-6) << r.method;
    EXPECT_LT(std::abs(r.err_v0_px) / 239, 1e-6) << r.method;
    EXPECT_LT(r.rot_err_deg, float32 ? 5e-5 : 1e-6) << r.method;
    EXPECT_LT(r.xc_err_m, float32 ? 1e-5 : 1e-6) << r.method;
  }
  EXPECT_EQ(rows[1].method, "zhang");
  EXPECT_EQ(rows[2].method, "zhang_handeye");
}

INSTANTIATE_TEST_SUITE_P(BothCases, RigRecovery,
                         ::testing::Values(CalibrationCase::kMovingCamera,
                                           CalibrationCase::kFixedCamera));

// Rotation about one fixed axis cannot determine a hand-eye problem: a failed row that says so.
TEST(Runner, DegenerateHandEyeIsReported) {
  ScenarioConfig s = LoadOne("tests/fixtures/rig_moving.yaml");
  s.trials = 1;
  EnableOnly(&s, {"zhang", "zhang_handeye"});
  s.motion.w_cos.setZero();
  s.motion.w_sin = Eigen::Vector3d(0.15, 0.2, 0.1);
  const std::vector<RunRow> rows = RunTrial(s, 0);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, "ok");
  EXPECT_EQ(rows[1].status, "failed");
  EXPECT_NE(rows[1].message.find("degenerate"), std::string::npos) << rows[1].message;
}

TEST(Runner, BadScenarioGivesAFailedRowNotACrash) {
  ScenarioConfig s = NoisyShortScenario();
  s.trials = 1;
  s.points.xyz.push_back({0, -50, 0});  // Behind the camera.
  const std::vector<RunRow> rows = RunTrial(s, 0);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].status, "failed");
  EXPECT_NE(rows[0].message.find("behind the camera"), std::string::npos) << rows[0].message;
}

// tests/fixtures/double_sphere.yaml (configs/examples/; a 190 deg lens, oracle corners, 0.1 px
// noise): the pinhole methods refuse the lens with the reason and the trial goes on; zhang's wide
// start and ceres recover f within kWideFocalTolPx. Measured |f.ku error| 0.51 px (zhang) and 0.51
// px (ceres, std 0.30) on trial 0; 1.5 px is 5 of ceres' std.
constexpr double kWideFocalTolPx = 1.5;
TEST(Runner, PinholeMethodsRefuseAWideLensAndTheOthersCalibrateIt) {
  ScenarioConfig s = LoadOne("tests/fixtures/double_sphere.yaml");
  s.trials = 1;
  const std::vector<RunRow> rows = RunTrial(s, 0);
  int refused = 0;
  for (const RunRow& r : rows) {
    const bool pinhole = r.method == "adaptive" || r.method == "dlt" || r.method == "zhang_pinhole";
    if (pinhole) {
      EXPECT_EQ(r.status, "failed") << r.method;
      EXPECT_NE(r.message.find("assumes a pinhole projection; the camera's lens is double-sphere"),
                std::string::npos)
          << r.method << ": " << r.message;
      ++refused;
    } else {
      ASSERT_EQ(r.status, "ok") << r.method << ": " << r.message;
      EXPECT_LT(std::abs(r.err_fku_px), kWideFocalTolPx) << r.method;
    }
  }
  EXPECT_EQ(refused, 3);
}

TEST(Table, ReferenceCheckComputesWorstDeviation) {
  ScenarioConfig s;
  s.name = "x";
  s.reference.fku_px = 800;
  s.reference.v0_px = 200;
  RunRow row;
  row.scenario = "x";
  row.method = "adaptive";
  row.fku_px = 808;  // 1%
  row.v0_px = 190;   // 5%
  const ReferenceCheck check = CheckAgainstReference(s, {row});
  EXPECT_TRUE(check.has_reference);
  EXPECT_NEAR(check.worst_relative_deviation, 0.05, 1e-12);
  EXPECT_EQ(check.worst_field, "v0");
  EXPECT_NE(ThesisTable({s}, {row}).find("worst 5.00% (v0)"), std::string::npos);
}

}  // namespace
}  // namespace calibench
