// The sweep harness: expansion of `sweep:`, shared measurements, the run directory (streaming,
// thread-count independence, shards and merge, resume) and summary.csv against an independent
// computation from runs.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/config/config_io.h"
#include "bench/run/csv.h"
#include "bench/run/run_dir.h"
#include "bench/run/runner.h"
#include "bench/run/summary.h"
#include "tests/common/scenario_yaml.h"
#include "tests/common/temp_files.h"
#include "util/random.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;
const std::string kSmall = std::string(CALIBENCH_SOURCE_DIR) + "/tests/bench/sweeps/small.yaml";

long col_of(const std::vector<std::string>& header, const std::string& name) {
  return std::find(header.begin(), header.end(), name) - header.begin();
}

RunConfig LoadSmall() {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfig(kSmall, &config, &why)) << why;
  return config;
}

std::string TempDir(const std::string& name) { return FreshTempDir("calibench_sweep_", name); }

TEST(Sweep, ExpandsTheCartesianProductWithMethodAxesFastest) {
  const RunConfig config = LoadSmall();
  ASSERT_EQ(config.scenarios.size(), 6u);  // 2 noise levels x 3 gains.
  const double sigma[] = {0.25, 0.25, 0.25, 0.5, 0.5, 0.5};
  const double alpha[] = {300, 1000, 3000, 300, 1000, 3000};
  for (int i = 0; i < 6; ++i) {
    const ScenarioConfig& s = config.scenarios[i];
    EXPECT_EQ(s.sweep_point.sweep, "small");
    EXPECT_EQ(s.sweep_point.index, i);
    EXPECT_EQ(s.sweep_point.measurement_index, i / 3);
    EXPECT_DOUBLE_EQ(s.measurements.noise.pixel_sigma_px, sigma[i]);
    EXPECT_DOUBLE_EQ(std::stod(MethodOption(s, "adaptive", "alpha")), alpha[i]);
    EXPECT_EQ(s.points.xyz.size(), 30u);
    EXPECT_EQ(s.points, config.scenarios[0].points)
        << "geometry is the scenario's, not the point's";
  }
  EXPECT_EQ(config.scenarios[1].name,
            "small[noise.pixel_sigma_px=0.25,methods.adaptive.alpha=1000]");
  // The points of a group share the instances the axis does not touch: same key, so copied.
  EXPECT_EQ(InstanceKey(config.scenarios[1], *config.scenarios[1].FindMethod("dlt")),
            InstanceKey(config.scenarios[0], *config.scenarios[0].FindMethod("dlt")));
  EXPECT_NE(InstanceKey(config.scenarios[1], *config.scenarios[1].FindMethod("adaptive")),
            InstanceKey(config.scenarios[0], *config.scenarios[0].FindMethod("adaptive")));
  // A measurement group shares its trial seeds; measurement points draw their own.
  EXPECT_EQ(config.scenarios[0].TrialSeedOf(2), config.scenarios[2].TrialSeedOf(2));
  EXPECT_NE(config.scenarios[0].TrialSeedOf(2), config.scenarios[3].TrialSeedOf(2));
  EXPECT_NE(config.scenarios[0].TrialSeedOf(2), config.scenarios[0].TrialSeedOf(3));
  EXPECT_EQ(MeasurementGroups(config.scenarios),
            (std::vector<std::vector<int>>{{0, 1, 2}, {3, 4, 5}}));
}

// paired_sweep: every measurement point runs the unswept scenario's trials, so rows pair by trial
// across points (the diagnostics of configs/diagnostics/); the points stay separate measurements.
TEST(Sweep, PairedSweepGivesEveryPointTheSameTrials) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(kSmall, &config, &why)) << why;
  const uint64_t unpaired = config.scenarios[3].TrialSeedOf(2);
  for (ScenarioConfig& s : config.scenarios) s.paired_sweep = true;
  for (const ScenarioConfig& s : config.scenarios) {
    EXPECT_EQ(s.TrialSeedOf(2), TrialSeed(s.seed, 2)) << s.name;
  }
  EXPECT_NE(config.scenarios[3].TrialSeedOf(2), unpaired);
  EXPECT_NE(config.scenarios[0].TrialSeedOf(2), config.scenarios[0].TrialSeedOf(3));
  EXPECT_EQ(MeasurementGroups(config.scenarios),
            (std::vector<std::vector<int>>{{0, 1, 2}, {3, 4, 5}}));
}

RunConfig FromString(const std::string& yaml) {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfigFromString(
      yaml, std::string(CALIBENCH_SOURCE_DIR) + "/tests/bench/sweeps/x.yaml", &config, &why))
      << why;
  return config;
}

std::string SweepError(const std::string& sweep) {
  RunConfig config;
  std::string why;
  EXPECT_FALSE(LoadRunConfigFromString(
      "base: ../../fixtures/thesis/sim03.yaml\nscenario: {name: e}\nsweep:\n" + sweep,
      std::string(CALIBENCH_SOURCE_DIR) + "/tests/bench/sweeps/x.yaml", &config, &why));
  return why;
}

TEST(Sweep, RangesAndWholeSectionFields) {
  const std::string head = "base: ../../fixtures/thesis/sim03.yaml\nscenario: {name: r}\nsweep:\n";
  // Linear range: 0, 0.25, ..., 1 (5 values; the end is included despite rounding).
  RunConfig c =
      FromString(head + "  - {field: noise.pixel_sigma_px, range: {from: 0, to: 1, step: 0.25}}\n");
  ASSERT_EQ(c.scenarios.size(), 5u);
  EXPECT_DOUBLE_EQ(c.scenarios[4].measurements.noise.pixel_sigma_px, 1.0);
  // Log range: 10, 100, 1000, 10000.
  c = FromString(
      head + "  - {field: methods.adaptive.alpha, range: {from: 10, to: 10000, log_step: 10}}\n");
  ASSERT_EQ(c.scenarios.size(), 4u);
  EXPECT_EQ(MethodOption(c.scenarios[3], "adaptive", "alpha"), "10000");
  // points and motion come from the base chain as whole sections: the preset and count survive.
  c = FromString(head +
                 "  - {field: points.count, values: [4, 6]}\n  - {field: motion.preset, values: "
                 "[small, large]}\n");
  ASSERT_EQ(c.scenarios.size(), 4u);
  EXPECT_EQ(c.scenarios[0].points.xyz.size(), 4u);
  EXPECT_EQ(c.scenarios[3].points.xyz.size(), 6u);
  EXPECT_EQ(c.scenarios[1].motion_preset, ThesisMotion::kLarge);
  // The resolved configuration reads back to the same sweep points.
  RunConfig again;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(ResolvedYaml(c), "resolved.yaml", &again, &why)) << why;
  ASSERT_EQ(again.scenarios.size(), 4u);
  EXPECT_EQ(again.scenarios[3].name, c.scenarios[3].name);
  EXPECT_EQ(again.scenarios[3].sweep_point.params, c.scenarios[3].sweep_point.params);
  EXPECT_EQ(again.scenarios[3].sweep_point.measurement_index, 3);
}

TEST(Sweep, BadAxesNameTheFileFieldAndReason) {
  std::string why = SweepError("  - {field: noise.pixel_sigma, values: [1]}\n");
  EXPECT_NE(why.find("x.yaml"), std::string::npos) << why;
  EXPECT_NE(why.find("pixel_sigma"), std::string::npos) << why;
  why = SweepError("  - {field: colour, values: [1]}\n");
  EXPECT_NE(why.find("'colour' is not a scenario field"), std::string::npos) << why;
  why = SweepError("  - {field: noise.pixel_sigma_px, range: {from: 1, to: 0, step: 1}}\n");
  EXPECT_NE(why.find("from <= to"), std::string::npos) << why;
  why = SweepError("  - {field: methods.adaptive.alpha, range: {from: 0, to: 10, log_step: 10}}\n");
  EXPECT_NE(why.find("must be > 0 with log_step"), std::string::npos) << why;
  why = SweepError("  - {field: noise.pixel_sigma_px, values: [-1]}\n");
  EXPECT_NE(why.find("noise.pixel_sigma_px=-1"), std::string::npos) << why;
  why = SweepError("  - {field: trials, values: []}\n");
  EXPECT_NE(why.find("non-empty list"), std::string::npos) << why;
}

// Method-only points reuse the group's measurements and the batch rows: the copies equal what a
// standalone run of that point computes.
TEST(Sweep, GroupSharesMeasurementsAndBatchRows) {
  const RunConfig config = LoadSmall();
  std::vector<const ScenarioConfig*> group = {&config.scenarios[0], &config.scenarios[1],
                                              &config.scenarios[2]};
  const std::vector<RunRow> rows = RunGroupTrial(group, 1, nullptr, GroupTrialOptions());
  ASSERT_EQ(rows.size(), 9u);  // 3 points x (adaptive, dlt, ceres).
  const std::vector<RunRow> alone = RunTrial(config.scenarios[2], 1);
  ASSERT_EQ(alone.size(), 3u);
  for (int m = 0; m < 3; ++m) {
    std::vector<std::string> shared = RunRowFields(rows[6 + m]), own = RunRowFields(alone[m]);
    EXPECT_EQ(shared, own) << alone[m].method;
  }
  EXPECT_FALSE(rows[6].reused);  // adaptive runs at every gain...
  EXPECT_TRUE(rows[7].reused);   // ...dlt and ceres once.
  EXPECT_TRUE(rows[8].reused);
  EXPECT_NE(rows[0].theta_err_norm, rows[6].theta_err_norm);
  EXPECT_EQ(rows[1].fku_px, rows[7].fku_px);
}

// tests/fixtures/named_instances.yaml (configs/examples/): two adaptive gains and two ceres
// refinements side by side. Every trial is one task (one measurement pass) giving 4 distinct rows
// per sweep point; the axis on adaptive-a100 re-runs that instance only, and the other three are
// copied at later points.
TEST(Sweep, NamedInstancesGiveTheirOwnRowsAndShareTheMeasurements) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(
      std::string(CALIBENCH_SOURCE_DIR) + "/tests/fixtures/named_instances.yaml", &config, &why))
      << why;
  ASSERT_EQ(config.scenarios.size(), 3u);
  for (ScenarioConfig& s : config.scenarios) {
    s.trials = 2;
    s.duration_s = 40;  // 80 frames: enough for every method, quick under the sanitizers.
  }
  EXPECT_EQ(MethodOption(config.scenarios[2], "adaptive-a100", "alpha"), "300");
  EXPECT_EQ(MethodOption(config.scenarios[2], "adaptive-a1000", "alpha"), "1000");
  EXPECT_EQ(MeasurementGroups(config.scenarios), (std::vector<std::vector<int>>{{0, 1, 2}}));
  std::vector<const ScenarioConfig*> group;
  for (const ScenarioConfig& s : config.scenarios) group.push_back(&s);
  const std::vector<RunRow> rows = RunGroupTrial(group, 1, nullptr, GroupTrialOptions());
  const std::vector<std::string> names = {"adaptive-a100", "adaptive-a1000", "ceres",
                                          "ceres-k2-huber"};
  ASSERT_EQ(rows.size(), 3u * names.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].method, names[i % 4]);
    EXPECT_EQ(rows[i].status, "ok") << rows[i].method << ": " << rows[i].message;
    EXPECT_EQ(rows[i].reused, i >= 4 && i % 4 != 0) << i;
    EXPECT_EQ(rows[i].measure_ms > 0, i < 4) << "one measurement pass, counted once";
  }
  // Four distinct estimates per point; the swept gain changes only its own instance.
  for (int m = 0; m < 4; ++m) {
    for (int n = m + 1; n < 4; ++n) EXPECT_NE(rows[m].fku_px, rows[n].fku_px) << m << " " << n;
  }
  EXPECT_NE(rows[0].fku_px, rows[4].fku_px);
  for (int m = 1; m < 4; ++m) EXPECT_EQ(rows[m].fku_px, rows[4 + m].fku_px);
  // The copies equal what a standalone run of the last point computes.
  const std::vector<RunRow> alone = RunTrial(config.scenarios[2], 1);
  ASSERT_EQ(alone.size(), 4u);
  for (int m = 0; m < 4; ++m) {
    std::vector<std::string> a = RunRowFields(alone[m]), b = RunRowFields(rows[8 + m]);
    EXPECT_EQ(a, b) << names[m];
  }
}

// The map form still works, with name = type: a `zhang:` entry configures zhang_handeye too, and an
// override of one instance leaves the others as they are.
TEST(Sweep, MapFormConfiguresInstancesByName) {
  const RunConfig c = FromString(
      "base: ../../fixtures/rig.yaml\nscenario:\n  name: m\n"
      "  methods: {zhang: {max_views: 12}, ceres: {loss: cauchy}}\n");
  const ScenarioConfig& s = c.scenarios.at(0);
  ASSERT_EQ(s.methods.size(), MethodTypes().size() + 2);  // One per type, and rig.yaml's twins.
  EXPECT_EQ(MethodOption(s, "zhang", "max_views"), "12");
  EXPECT_EQ(MethodOption(s, "zhang_handeye", "max_views"), "12");
  EXPECT_EQ(MethodOption(s, "ceres", "loss"), "cauchy");
  EXPECT_EQ(MethodOption(s, "ceres", "init"), "zhang");  // From rig.yaml, kept.
  std::vector<std::string> enabled;
  for (const MethodInstance* m : s.EnabledMethods()) enabled.push_back(m->name);
  EXPECT_EQ(enabled, (std::vector<std::string>{"adaptive", "dlt", "zhang", "zhang_handeye", "ceres",
                                               "ceres_zhang_views_k2", "ceres_zhang_views"}));
}

// motion.random_phase: a trial's scene comes from its seed (the same seed, the same motion;
// another seed, another phase of the same profile); without it every trial has one motion.
TEST(Sweep, RandomPhaseGivesEachTrialItsOwnViews) {
  const RunConfig c = FromString("base: ../../fixtures/rig.yaml\nscenario: {name: p}\n");
  const ScenarioConfig& s = c.scenarios.at(0);
  ASSERT_TRUE(s.motion_random_phase);
  const auto pose_at = [&](int trial) {
    return s.MakeScene(s.TrialSeedOf(trial)).motion.WorldFromBody(20.0);
  };
  EXPECT_EQ(pose_at(0).rotation, pose_at(0).rotation);
  EXPECT_GT((pose_at(0).rotation - pose_at(1).rotation).norm(), 1e-3);
  ScenarioConfig fixed = s;
  fixed.motion_random_phase = false;
  EXPECT_EQ(fixed.MakeScene(s.TrialSeedOf(0)).motion.WorldFromBody(20.0).rotation,
            fixed.MakeScene(s.TrialSeedOf(1)).motion.WorldFromBody(20.0).rotation);
}

// A map key naming a new instance with `type:` adds it (enabled); `type:` on an existing name is
// refused.
TEST(Sweep, MapFormAddsATypedInstance) {
  const RunConfig c = FromString(
      "base: ../../fixtures/rig.yaml\nscenario:\n  name: m\n"
      "  methods: {twin: {type: ceres, init: zhang, views: init}}\n");
  const MethodInstance* twin = c.scenarios.at(0).FindMethod("twin");
  ASSERT_NE(twin, nullptr);
  EXPECT_EQ(twin->type, "ceres");
  EXPECT_TRUE(twin->enabled);
  EXPECT_EQ(MethodOption(c.scenarios.at(0), "twin", "views"), "init");
  RunConfig refused;
  std::string error;
  EXPECT_FALSE(LoadRunConfigFromString(
      "base: ../../fixtures/rig.yaml\nscenario:\n  name: m\n"
      "  methods: {ceres: {type: dlt}}\n",
      std::string(CALIBENCH_SOURCE_DIR) + "/tests/bench/sweeps/x.yaml", &refused, &error));
  EXPECT_NE(error.find("methods.ceres.type: 'ceres' is already an instance of type ceres"),
            std::string::npos)
      << error;
}

TEST(RunDir, FilesDoNotDependOnThreadsShardsOrInterruptions) {
  const RunConfig config = LoadSmall();
  RunDirOptions one;
  one.out_dir = TempDir("t1");
  one.threads = 1;
  ASSERT_TRUE(RunToDirectory(config, one).ok);
  const std::string runs = Slurp(one.out_dir + "/runs.csv");
  const std::string summary = Slurp(one.out_dir + "/summary.csv");
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 1 + 6 * 4 * 3);
  EXPECT_FALSE(fs::exists(one.out_dir + "/run.partial"));

  RunDirOptions two = one;
  two.out_dir = TempDir("t2");
  two.threads = 2;
  two.max_buffered_tasks = 1;  // The tightest window still gives the same bytes.
  ASSERT_TRUE(RunToDirectory(config, two).ok);
  EXPECT_EQ(Slurp(two.out_dir + "/runs.csv"), runs);
  EXPECT_EQ(Slurp(two.out_dir + "/summary.csv"), summary);
  EXPECT_EQ(Slurp(two.out_dir + "/curves.csv"), Slurp(one.out_dir + "/curves.csv"));

  std::vector<std::string> shards;
  for (int k = 1; k <= 3; ++k) {
    RunDirOptions o;
    o.out_dir = TempDir("shard" + std::to_string(k));
    o.shard.index = k;
    o.shard.count = 3;
    o.threads = 2;
    const RunDirSummary s = RunToDirectory(config, o);
    ASSERT_TRUE(s.ok) << s.message;
    EXPECT_EQ(s.tasks_total, k == 3 ? 2 : 3);  // 8 tasks: 0 3 6 | 1 4 7 | 2 5.
    shards.push_back(o.out_dir);
  }
  std::string why;
  const std::string merged = TempDir("merged");
  ASSERT_TRUE(MergeRunDirectories({shards[2], shards[0], shards[1]}, merged, &why)) << why;
  EXPECT_EQ(Slurp(merged + "/runs.csv"), runs);
  EXPECT_EQ(Slurp(merged + "/summary.csv"), summary);
  EXPECT_FALSE(MergeRunDirectories({shards[0], shards[1]}, TempDir("m2"), &why));
  EXPECT_NE(why.find("3 shards"), std::string::npos) << why;

  // Interrupted after 3 tasks, with a torn row appended as a kill mid-write would leave it.
  RunDirOptions cut = two;
  cut.out_dir = TempDir("cut");
  int written = 0;
  cut.should_stop = [&written] { return ++written >= 3; };
  EXPECT_FALSE(RunToDirectory(config, cut).ok);
  { std::ofstream(cut.out_dir + "/run.partial/runs.csv", std::ios::app) << "small[torn,0,"; }
  cut.should_stop = nullptr;
  cut.resume = true;
  const RunDirSummary resumed = RunToDirectory(config, cut);
  ASSERT_TRUE(resumed.ok) << resumed.message;
  EXPECT_EQ(resumed.tasks_resumed, 3);
  EXPECT_EQ(resumed.tasks_run, 5);
  EXPECT_EQ(Slurp(cut.out_dir + "/runs.csv"), runs);
  EXPECT_EQ(Slurp(cut.out_dir + "/summary.csv"), summary);
  // Resuming with another configuration is refused, naming the file.
  RunConfig other = config;
  other.scenarios[0].trials = 5;
  cut.out_dir = TempDir("cut2");
  cut.resume = false;
  cut.should_stop = [] { return true; };
  RunToDirectory(config, cut);
  cut.resume = true;
  cut.should_stop = nullptr;
  const RunDirSummary refused = RunToDirectory(other, cut);
  EXPECT_FALSE(refused.ok);
  EXPECT_NE(refused.message.find("config.resolved.yaml"), std::string::npos) << refused.message;
}

// The type-7 percentile written out independently of bench/run/stats.h (Hyndman & Fan's
// definition, 1-based: h = (n - 1) p + 1, x_floor(h) + (h - floor(h)) (x_floor(h)+1 - x_floor(h))),
// so that a mistake in Quantile() shows against it.
double Percentile7(std::vector<double> x, double p) {
  std::sort(x.begin(), x.end());
  const double h = (static_cast<double>(x.size()) - 1.0) * p + 1.0;
  const size_t below = static_cast<size_t>(std::floor(h));  // 1-based.
  if (below >= x.size()) return x.back();
  return x[below - 1] + (h - static_cast<double>(below)) * (x[below] - x[below - 1]);
}

// summary.csv against the statistics computed here, independently of the code's Quantile(), from
// runs.csv's own column. Mutation tried: Quantile() at position q * n (bench/run/stats.cc) fails
// the percentiles here and in the test below.
TEST(Summary, MatchesAnIndependentComputation) {
  const RunConfig config = LoadSmall();
  RunDirOptions o;
  o.out_dir = TempDir("summary");
  ASSERT_TRUE(RunToDirectory(config, o).ok);
  std::ifstream runs(o.out_dir + "/runs.csv");
  CsvReader reader(&runs);
  std::vector<std::string> header, fields;
  std::string why;
  ASSERT_TRUE(reader.Next(&header, &why));
  const auto col = [&](const std::string& n) {
    return std::find(header.begin(), header.end(), n) - header.begin();
  };
  std::vector<double> errors, crlb;
  const std::string scenario = config.scenarios[4].name;
  while (reader.Next(&fields, &why)) {
    if (fields[col("scenario")] != scenario || fields[col("method")] != "ceres") continue;
    errors.push_back(std::stod(fields[col("err_fku_px")]));
    crlb.push_back(std::stod(fields[col("crlb_fku_px")]));
  }
  ASSERT_EQ(errors.size(), 4u);
  double sum_sq = 0;
  std::vector<double> abs_errors;
  for (double e : errors) sum_sq += e * e, abs_errors.push_back(std::abs(e));
  std::ifstream summary(o.out_dir + "/summary.csv");
  CsvReader s(&summary);
  ASSERT_TRUE(s.Next(&header, &why));
  bool found = false;
  const auto value = [&](const char* column) { return std::stod(fields[col_of(header, column)]); };
  while (s.Next(&fields, &why)) {
    if (fields[0] != scenario || fields[col_of(header, "method")] != "ceres" ||
        fields[col_of(header, "metric")] != "err_fku_px") {
      continue;
    }
    found = true;
    EXPECT_EQ(fields[col_of(header, "n")], "4");
    EXPECT_EQ(fields[col_of(header, "n_failed")], "0");
    // %.10g in the file: 1e-9 relative.
    const auto near = [](double a, double b) {
      return std::abs(a - b) <= 1e-9 * std::abs(b) + 1e-15;
    };
    EXPECT_PRED2(near, value("median"), Percentile7(errors, 0.5));
    EXPECT_PRED2(near, value("p2_5"), Percentile7(errors, 0.025));
    EXPECT_PRED2(near, value("p97_5"), Percentile7(errors, 0.975));
    EXPECT_PRED2(near, value("median_abs"), Percentile7(abs_errors, 0.5));
    EXPECT_PRED2(near, value("p97_5_abs"), Percentile7(abs_errors, 0.975));
    EXPECT_PRED2(near, value("rmse"), std::sqrt(sum_sq / 4));
    EXPECT_PRED2(near, value("crlb"), Percentile7(crlb, 0.5));
  }
  EXPECT_TRUE(found);
}

// summary.csv of a runs.csv written by hand, against values worked out by hand (no code of the
// project computes them).
TEST(Summary, KnownValuesOfAHandWrittenRunsCsv) {
  const std::string dir = TempDir("summary_known");
  fs::create_directories(dir);
  const std::string runs = dir + "/runs.csv";
  // err_fku_px of the ok rows: -3, -1, 0, 2, 5 (and one NaN); a failed row's 100 is left out.
  std::ofstream(runs) << "scenario,sweep,point,params,method,status,err_fku_px,crlb_fku_px,"
                         "std_fku_px\n"
                         "s,s,0,,m,ok,-3,0.5,1\n"
                         "s,s,0,,m,ok,-1,0.5,2\n"
                         "s,s,0,,m,ok,0,0.7,3\n"
                         "s,s,0,,m,ok,2,0.9,4\n"
                         "s,s,0,,m,ok,5,0.9,5\n"
                         "s,s,0,,m,ok,nan,nan,6\n"
                         "s,s,0,,m,failed,100,1.0,100\n";
  std::string text, why;
  ASSERT_TRUE(SummarizeRuns(runs, &text, &why)) << why;
  std::istringstream in(text);
  CsvReader reader(&in);
  std::vector<std::string> header, fields;
  ASSERT_TRUE(reader.Next(&header, &why));
  bool found = false;
  while (reader.Next(&fields, &why)) {
    if (fields[col_of(header, "metric")] != "err_fku_px") continue;
    found = true;
    const auto value = [&](const char* column) {
      return std::stod(fields[col_of(header, column)]);
    };
    EXPECT_EQ(fields[col_of(header, "n")], "7");
    EXPECT_EQ(fields[col_of(header, "n_failed")], "1");
    EXPECT_EQ(fields[col_of(header, "n_used")], "5");
    constexpr double kDigits = 1e-9;  // The file's %.10g.
    EXPECT_NEAR(value("median"), 0.0, kDigits);
    EXPECT_NEAR(value("mean"), 0.6, kDigits);
    EXPECT_NEAR(value("std"), std::sqrt(37.2 / 4), kDigits);  // Squared deviations sum to 37.2.
    // Sorted -3, -1, 0, 2, 5: h = 4 * 0.025 = 0.1 -> -3 + 0.1 * 2; h = 3.9 -> 2 + 0.9 * 3.
    EXPECT_NEAR(value("p2_5"), -2.8, kDigits);
    EXPECT_NEAR(value("p97_5"), 4.7, kDigits);
    EXPECT_NEAR(value("rmse"), std::sqrt(39.0 / 5), kDigits);
    // The bound's median over every row with a finite one (the failed row's 1.0 included):
    // 0.5, 0.5, 0.7, 0.9, 0.9, 1.0 -> 0.8.
    EXPECT_NEAR(value("crlb"), 0.8, kDigits);
    EXPECT_NEAR(value("rmse_over_crlb"), std::sqrt(39.0 / 5) / 0.8, kDigits);
    // |value| sorted 0, 1, 2, 3, 5: median 2, 0 + 0.1 * 1, 3 + 0.9 * 2.
    EXPECT_NEAR(value("median_abs"), 2.0, kDigits);
    EXPECT_NEAR(value("p2_5_abs"), 0.1, kDigits);
    EXPECT_NEAR(value("p97_5_abs"), 4.8, kDigits);
    // The reported std's median over the ok rows (the NaN row's 6 included): 1..6 -> 3.5.
    EXPECT_NEAR(value("std_reported"), 3.5, kDigits);
  }
  EXPECT_TRUE(found);
}

TEST(Csv, ReaderHandlesQuotesAndReportsCutRecords) {
  std::istringstream in("a,\"b,\"\"c\"\"\nd\",e\nf,g");
  CsvReader reader(&in);
  std::vector<std::string> fields;
  std::string why;
  ASSERT_TRUE(reader.Next(&fields, &why));
  EXPECT_EQ(fields, (std::vector<std::string>{"a", "b,\"c\"\nd", "e"}));
  EXPECT_FALSE(reader.Next(&fields, &why));
  EXPECT_NE(why.find("no newline"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
