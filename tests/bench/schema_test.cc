// The metric table (metrics/metric_table.h) and what is made of it: every CSV column follows the
// naming rule, runs.csv lays out every column the table declares, schema.json describes every
// column of every file and each sweep's report role, and is written into the run directory.
#include "bench/run/schema.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>

#include "bench/config/config_io.h"
#include "bench/run/run_dir.h"
#include "bench/run/run_row.h"
#include "bench/run/summary.h"
#include "methods/registry.h"
#include "metrics/metric_table.h"
#include "metrics/tracking.h"
#include "tests/common/scenario_yaml.h"
#include "tests/common/temp_files.h"

namespace calibench {
namespace {

const std::vector<std::pair<std::string, const std::vector<ColumnInfo>*>>& Files() {
  static const std::vector<std::pair<std::string, const std::vector<ColumnInfo>*>> files = {
      {"runs.csv", &RunRowColumns()},
      {"summary.csv", &SummaryColumns()},
      {"timings.csv", &TimingColumns()},
      {"curves.csv", &CurveColumns()},
      {"events.csv", &EventColumns()},
      {"tracks.csv", &TrackColumns()},
      {"track_errors.csv", &TrackErrorColumns()},
      {"track_bands.csv", &TrackBandColumns()}};
  return files;
}

bool EndsWith(const std::string& text, const std::string& tail) {
  return text.size() >= tail.size() &&
         text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

TEST(MetricTable, EveryColumnFollowsTheNamingRule) {
  const std::set<std::string> units = {"px", "deg", "m", "s", "ms", "us"};
  for (const auto& [file, columns] : Files()) {
    std::set<std::string> names;
    for (const ColumnInfo& c : *columns) {
      EXPECT_TRUE(names.insert(c.name).second) << file << ": " << c.name << " twice";
      EXPECT_FALSE(c.doc.empty()) << file << ": " << c.name;
      for (char ch : c.name) {
        EXPECT_TRUE(std::islower(static_cast<unsigned char>(ch)) || std::isdigit(ch) || ch == '_')
            << file << ": " << c.name;
      }
      if (c.unit.empty()) continue;
      EXPECT_TRUE(units.count(c.unit)) << file << ": " << c.name << " in " << c.unit;
      EXPECT_TRUE(EndsWith(c.name, "_" + c.unit)) << file << ": " << c.name << " is in " << c.unit;
    }
  }
  // A dimensionless quantity has no unit suffix: none of a run's ends in one.
  for (const MetricSpec& m : RunQuantities()) {
    if (std::string(m.unit).empty()) {
      for (const std::string& u : units) EXPECT_FALSE(EndsWith(m.name, "_" + u)) << m.name;
    }
  }
}

TEST(MetricTable, RunsCsvCarriesEveryDeclaredColumnAndTheTracksTheTrackedOnes) {
  const std::vector<std::string>& header = RunRowHeader();
  for (const MetricSpec& m : RunQuantities()) {
    for (MetricColumn kind : {kValueColumn, kErrorColumn, kStdColumn, kCrlbColumn}) {
      if (!(m.columns & kind)) continue;
      const std::string name = ColumnName(m, kind);
      EXPECT_NE(std::find(header.begin(), header.end(), name), header.end()) << name;
    }
  }
  EXPECT_EQ(ColumnName(Metric::kFku, kErrorColumn), "err_fku_px");
  EXPECT_EQ(ColumnName(Metric::kU0, kStdColumn), "std_u0_px");
  EXPECT_EQ(ColumnName(Metric::kPhi, kCrlbColumn), "crlb_phi_deg");
  EXPECT_THROW(ColumnName(Metric::kRotErr, kErrorColumn), std::logic_error);
  // The tracked quantities are the table's, in TrackValues order, with the same names everywhere.
  EXPECT_EQ(std::string(TrackQuantityNames()[0]), "roll_deg");
  EXPECT_EQ(std::string(TrackQuantityNames()[3]), "fku_px");
  const std::vector<std::string>& tracks = TrackHeader();
  for (const char* q : TrackQuantityNames()) {
    EXPECT_NE(std::find(tracks.begin(), tracks.end(), std::string("est_") + q), tracks.end()) << q;
    EXPECT_NE(std::find(header.begin(), header.end(), std::string("err_") + q), header.end()) << q;
  }
  EXPECT_TRUE(TrackQuantityIsAngle(1));
  EXPECT_FALSE(TrackQuantityIsAngle(5));
  // summary.csv's metrics are runs.csv columns.
  for (const std::string& m : SummaryMetrics()) {
    EXPECT_NE(std::find(header.begin(), header.end(), m), header.end()) << m;
  }
}

// The registered types' declared outputs sit in their slot, after converge_time_s, in registry
// order: in runs.csv and among the quantities of a run (where pe_min_eig has always been).
TEST(MetricTable, MethodOutputsSitInTheirSlot) {
  const std::vector<std::string>& header = RunRowHeader();
  const std::vector<MetricSpec>& quantities = RunQuantities();
  const auto column = std::find(header.begin(), header.end(), "converge_time_s");
  ASSERT_NE(column, header.end());
  auto quantity = std::find_if(quantities.begin(), quantities.end(),
                               [](const MetricSpec& m) { return m.id == kMethodOutputsAfter; });
  ASSERT_NE(quantity, quantities.end());
  size_t i = 1;
  for (const OutputSpec& o : DeclaredOutputs()) {
    ASSERT_LT(column + i, header.end());
    EXPECT_EQ(*(column + i), o.name);
    ASSERT_LT(quantity + i, quantities.end());
    EXPECT_EQ(std::string((quantity + i)->name), o.name);
    EXPECT_EQ((quantity + i)->id, Metric::kMethodOutput);
    ++i;
  }
  EXPECT_EQ(*(column + i), "ortho_defect");
  EXPECT_EQ((quantity + i)->id, Metric::kOrthoDefect);
  // adaptive declares pe_min_eig; it is not one of the metric table's own.
  EXPECT_NE(std::find(header.begin(), header.end(), "pe_min_eig"), header.end());
  for (const MetricSpec& m : MetricTable()) EXPECT_NE(std::string(m.name), "pe_min_eig");
}

RunConfig Load(const std::string& yaml) {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfigFromString(yaml, "test.yaml", &config, &why)) << why;
  return config;
}

TEST(Schema, DescribesEveryColumnAndEachSweepsRole) {
  const RunConfig config = Load(
      "scenario:\n  name: n\n  duration_s: 10\n  report: {role: noise}\n"
      "  truth:\n    intrinsics: {fku_px: 800, fkv_px: 810, phi_deg: 88, u0_px: 320, v0_px: 240}\n"
      "    R_C: [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]\n    x_C: [0, -2, 0.5]\n"
      "  points: {preset: thesis, count: 10}\n"
      "sweep:\n  - {field: noise.pixel_sigma_px, values: [0.1, 0.2]}\n");
  ASSERT_EQ(config.scenarios.size(), 2u);
  const std::string json = SchemaJson(config);
  for (const auto& [file, columns] : Files()) {
    const size_t at = json.find("\"" + file + "\": [");
    ASSERT_NE(at, std::string::npos) << file;
    size_t from = at;
    for (const ColumnInfo& c : *columns) {  // In file order.
      const size_t next =
          json.find("{\"name\": \"" + c.name + "\", \"unit\": \"" + c.unit + "\"", from);
      EXPECT_NE(next, std::string::npos) << file << ": " << c.name;
      if (next != std::string::npos) from = next;
    }
  }
  EXPECT_NE(json.find("{\"name\": \"fku_px\", \"unit\": \"px\", \"label\": \"f·ku\""),
            std::string::npos);
  EXPECT_NE(json.find("\"columns\": {\"value\": \"fku_px\", \"error\": \"err_fku_px\", \"std\": "
                      "\"std_fku_px\", \"crlb\": \"crlb_fku_px\"}"),
            std::string::npos);
  EXPECT_NE(json.find("\"summary_metric\": \"err_pitch_deg\", \"ranked\": true, \"target\": 0.1"),
            std::string::npos);
  EXPECT_NE(json.find("{\"sweep\": \"n\", \"role\": \"noise\", \"detections\": \"oracle\", "
                      "\"axes\": [\"noise.pixel_sigma_px\"], \"points\": 2, \"trials\": 1, "
                      "\"tracks\": false}"),
            std::string::npos)
      << json.substr(json.find("\"sweeps\""));
  // Per registered type: its family, its outputs and its windup law.
  for (const MethodType& t : MethodTypes()) {
    EXPECT_NE(json.find("{\"type\": \"" + t.name + "\", \"family\": \"" + ToString(t.family) +
                        "\", \"outputs\": ["),
              std::string::npos)
        << t.name;
  }
  EXPECT_NE(json.find("{\"type\": \"adaptive\", \"family\": \"adaptive\", \"outputs\": "
                      "[\"pe_min_eig\"], \"windup\": "
                      "{\"exponent\": \"alpha\", \"only_when_zero\": [\"forgetting_beta\", "
                      "\"reset_threshold\"]}}"),
            std::string::npos)
      << json.substr(json.find("\"methods\""));
  EXPECT_NE(
      json.find("{\"type\": \"dlt\", \"family\": \"batch\", \"outputs\": [], \"windup\": null}"),
      std::string::npos);
  EXPECT_NE(json.find("{\"type\": \"ekf\", \"family\": \"filter\""), std::string::npos);
}

TEST(Schema, IsWrittenIntoTheRunDirectory) {
  RunConfig config = Load(MinimalScenarioYaml(ScenarioYamlParts()));
  RunDirOptions o;
  o.out_dir = FreshTempDir("calibench_schema_", "run");
  ASSERT_TRUE(RunToDirectory(config, o).ok);
  EXPECT_EQ(Slurp(o.out_dir + "/schema.json"), SchemaJson(config));
  EXPECT_NE(Slurp(o.out_dir + "/schema.json").find("{\"sweep\": \"t\", \"role\": \"\""),
            std::string::npos);
}

TEST(Config, ReportRoleIsReadWrittenAndChecked) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(std::string(CALIBENCH_SOURCE_DIR) + "/configs/sweeps/noise.yaml",
                            &config, &why))
      << why;
  for (const ScenarioConfig& s : config.scenarios)
    EXPECT_EQ(s.report.role, ReportRole::kNoise) << s.name;
  ASSERT_TRUE(
      LoadRunConfig(std::string(CALIBENCH_SOURCE_DIR) + "/configs/dynamic/all.yaml", &config, &why))
      << why;
  for (const ScenarioConfig& s : config.scenarios)
    EXPECT_EQ(s.report.role, ReportRole::kDynamic) << s.name;
  EXPECT_NE(ResolvedYaml(config).find("report: {role: dynamic}"), std::string::npos);
  RunConfig bad;
  ScenarioYamlParts parts;
  parts.extra = "  report: {role: noisy}\n";
  EXPECT_FALSE(LoadRunConfigFromString(MinimalScenarioYaml(parts), "test.yaml", &bad, &why));
  EXPECT_NE(why.find("test.yaml:4:"), std::string::npos) << why;
  EXPECT_NE(
      why.find("scenario.report.role: 'noisy' is not one of: none, noise, points, gain, dynamic"),
      std::string::npos)
      << why;
  parts.extra = "  report: {rol: noise}\n";
  EXPECT_FALSE(LoadRunConfigFromString(MinimalScenarioYaml(parts), "test.yaml", &bad, &why));
  EXPECT_NE(why.find("did you mean 'role'"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
