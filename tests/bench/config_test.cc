#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "bench/config/config_io.h"
#include "methods/options.h"
#include "tests/common/scenario_yaml.h"

namespace calibench {
namespace {

// What the tests assert about particular scenarios is read from frozen copies (tests/fixtures/:
// editing a user-facing config cannot break them); only the round trip below reads configs/, to
// check that every shipped config loads and is written back whole.
const std::string kFixtures = std::string(CALIBENCH_SOURCE_DIR) + "/tests/fixtures/";
const std::string kConfigs = std::string(CALIBENCH_SOURCE_DIR) + "/configs/";

// The minimal scenario with `extra` lines; `truth_lines` replaces the R_C and x_C lines.
std::string Scenario(const std::string& extra = "", const std::string& truth_lines = "") {
  ScenarioYamlParts parts;
  parts.extra = extra;
  if (!truth_lines.empty()) parts.truth_lines = truth_lines;
  return MinimalScenarioYaml(parts);
}

std::string LoadError(const std::string& yaml) {
  RunConfig config;
  std::string why;
  EXPECT_FALSE(LoadRunConfigFromString(yaml, "test.yaml", &config, &why)) << yaml;
  return why;
}

TEST(Config, MinimalScenarioLoadsWithDefaults) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(Scenario(), "test.yaml", &config, &why)) << why;
  const ScenarioConfig& s = config.scenarios.at(0);
  EXPECT_EQ(s.points.xyz.size(), 10u);
  EXPECT_EQ(MethodOption(s, "adaptive", "alpha"), "1000");
  ASSERT_EQ(s.EnabledMethods().size(), 1u);  // The map form's default: adaptive only.
  EXPECT_EQ(s.EnabledMethods()[0]->name, "adaptive");
  EXPECT_EQ(s.trials, 1);
  EXPECT_EQ(s.calibration_case, CalibrationCase::kMovingCamera);
}

TEST(Config, UnknownKeyIsNamedWithLineAndSuggestion) {
  const std::string why = LoadError(Scenario("  methods: {adaptive: {alhpa: 5}}\n"));
  EXPECT_NE(why.find("test.yaml:4:"), std::string::npos) << why;
  EXPECT_NE(why.find("scenario.methods.adaptive.alhpa"), std::string::npos) << why;
  EXPECT_NE(why.find("did you mean 'alpha'"), std::string::npos) << why;
}

TEST(Config, WrongTypeIsNamed) {
  const std::string why = LoadError(Scenario("  trials: many\n"));
  EXPECT_NE(why.find("test.yaml:4:"), std::string::npos) << why;
  EXPECT_NE(why.find("scenario.trials: expected an integer, got 'many'"), std::string::npos) << why;
  const std::string why2 = LoadError(Scenario("", "    x_C: [0, 1]\n"));
  EXPECT_NE(why2.find("scenario.truth.x_C: expected a list of 3 numbers"), std::string::npos)
      << why2;
}

TEST(Config, MissingFieldIsNamed) {
  const std::string why = LoadError("scenario:\n  duration_s: 10\n  points: {preset: thesis}\n");
  EXPECT_NE(why.find("scenario.name: missing"), std::string::npos) << why;
  const std::string base = LoadError("base: nowhere.yaml\nscenario: {name: x}\n");
  EXPECT_NE(base.find("test.yaml:1:7: base: cannot open 'nowhere.yaml'"), std::string::npos)
      << base;
  EXPECT_NE(LoadError("{}\n").find("scenario: missing"), std::string::npos);
}

TEST(Config, OutOfRangeValuesAreNamed) {
  EXPECT_NE(LoadError(Scenario("  trials: 0\n")).find("scenario.trials: must be >= 1"),
            std::string::npos);
  EXPECT_NE(
      LoadError(Scenario("  noise: {pixel_sigma_px: -0.5}\n")).find("pixel_sigma_px must be >= 0"),
      std::string::npos);
  const std::string phi =
      LoadError("scenario:\n  name: t\n  truth:\n    intrinsics: {phi_deg: 190}\n");
  EXPECT_NE(phi.find("test.yaml:4:"), std::string::npos) << phi;
  EXPECT_NE(phi.find("scenario.truth.intrinsics: phi_deg must lie in (0, 180)"), std::string::npos)
      << phi;
  EXPECT_NE(LoadError(Scenario("  methods: {adaptive: {alpha: -3}}\n")).find("alpha must be"),
            std::string::npos);
}

TEST(Config, ImproperRotationIsRefusedUnlessAllowed) {
  const std::string improper = "    R_C: [[0, 1, 0], [0, 0, 1], [-1, 0, 0]]\n";
  const std::string why = LoadError(Scenario("", improper));
  EXPECT_NE(why.find("scenario.truth.R_C: rotation is improper"), std::string::npos) << why;
  EXPECT_NE(why.find("test.yaml:"), std::string::npos) << why;
  RunConfig config;
  std::string error;
  ASSERT_TRUE(LoadRunConfigFromString(
      Scenario("", improper + "    allow_improper_rotation: true\n"), "test.yaml", &config, &error))
      << error;
  EXPECT_TRUE(config.scenarios[0].truth.allow_improper_rotation);
  const std::string skewed =
      LoadError(Scenario("", "    R_C: [[1, 0.001, 0], [0, 1, 0], [0, 0, 1]]\n"));
  EXPECT_NE(skewed.find("not orthonormal"), std::string::npos) << skewed;
}

TEST(Config, MalformedYamlGivesLine) {
  const std::string why = LoadError("scenario:\n  name: [unclosed\n  trials: 1\n");
  EXPECT_NE(why.find("malformed YAML"), std::string::npos) << why;
  EXPECT_NE(why.find("test.yaml:"), std::string::npos) << why;
}

TEST(Config, ThesisEntryPointLoadsEverySimulationAndVariant) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(kFixtures + "thesis/all.yaml", &config, &why)) << why;
  ASSERT_EQ(config.scenarios.size(), 17u + 15u);  // sims 1-17, proper variants of cameras 2, 3.
  const ScenarioConfig& sim07 = config.scenarios[6];
  EXPECT_EQ(sim07.name, "sim07");
  EXPECT_EQ(sim07.points.xyz.size(), 5u);
  EXPECT_TRUE(sim07.truth.allow_improper_rotation);
  EXPECT_NEAR(sim07.truth.r_c.determinant(), -1, 1e-12);
  EXPECT_EQ(sim07.reference.fku_px, 868.0);
  const ScenarioConfig& sim15 = config.scenarios[14];
  EXPECT_EQ(sim15.trials, 50);
  EXPECT_NEAR(sim15.measurements.noise.point_sigma_m, std::sqrt(0.001), 1e-15);
  const ScenarioConfig& sim09 = config.scenarios[8];
  EXPECT_EQ(MethodOption(sim09, "adaptive", "alpha"), "5");
  const ScenarioConfig& proper = config.scenarios[17 + 4];  // sim07-proper (after 02, 04, 05, 06).
  EXPECT_EQ(proper.name, "sim07-proper");
  EXPECT_NEAR(proper.truth.r_c.determinant(), 1, 1e-12);
  EXPECT_FALSE(proper.truth.allow_improper_rotation);
  EXPECT_EQ(proper.points.xyz.size(), 5u);  // Inherited through base:.
  // A variant is its scenario with the override on top: the reference replaced as a whole (the
  // printed figures do not apply to it), the rest equal.
  EXPECT_EQ(proper.description, sim07.description + ", proper R_C");
  EXPECT_TRUE(std::isnan(proper.reference.fku_px));
  EXPECT_TRUE(std::isnan(proper.reference.theta_err_below));
  EXPECT_EQ(config.scenarios[17 + 1].reference.theta_err_below, 1e-4);  // sim04-proper.
  ScenarioConfig back = proper;
  back.name = sim07.name;
  back.sweep_point = sim07.sweep_point;
  back.description = sim07.description;
  back.truth = sim07.truth;
  back.reference = sim07.reference;
  back.source_file = sim07.source_file;
  EXPECT_TRUE(back == sim07);
}

TEST(Config, VariantsNameTheirScenariosAndRefuseAnUnknownOne) {
  const std::string two =
      "scenarios:\n  - {name: alpha, points: {preset: thesis}}\n"
      "  - {name: beta, points: {preset: thesis}, trials: 3}\n";
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(
      two + "variants:\n  - {suffix: v, of: [beta, alpha], scenario: {seed: 9}}\n", "v.yaml",
      &config, &why))
      << why;
  ASSERT_EQ(config.scenarios.size(), 4u);
  EXPECT_EQ(config.scenarios[2].name, "alpha-v");  // In the order of the scenarios they vary.
  EXPECT_EQ(config.scenarios[3].name, "beta-v");
  EXPECT_EQ(config.scenarios[3].trials, 3);
  EXPECT_EQ(config.scenarios[3].seed, 9u);
  why = LoadError(two + "variants:\n  - {suffix: v, of: [gamma, betta], scenario: {}}\n");
  EXPECT_NE(why.find("test.yaml:5:22: variants[0].of[0]: unknown scenario 'gamma'"),
            std::string::npos)
      << why;
  why = LoadError(two + "variants:\n  - {suffix: v, of: [betta], scenario: {}}\n");
  EXPECT_NE(why.find("did you mean 'beta'"), std::string::npos) << why;
  // A sweep's points vary into one sweep, named after it.
  ASSERT_TRUE(
      LoadRunConfigFromString("scenarios:\n  - {name: s, points: {preset: thesis}}\n"
                              "variants:\n  - {suffix: v, of: [s], scenario: {seed: 2}}\n",
                              "v.yaml", &config, &why))
      << why;
  EXPECT_EQ(config.scenarios.at(1).sweep_point.sweep, "s-v");
  why = LoadError(two + "variants:\n  - {suffix: v, of: [beta], scenario: {trials: 0}}\n");
  EXPECT_NE(why.find("variants[0].scenario.trials: must be >= 1"), std::string::npos) << why;
}

// Every scenario config shipped in configs/ (each .yaml but the Kalibr target files of
// configs/targets/, found by walking the tree: a config added later is covered without editing
// this list), resolved and read back, equals itself field by field (operator== compares the whole
// ScenarioConfig, the methods by their options), independently of the text: a field the writer
// drops fails here. The text is a fixed point as well.
std::vector<std::string> ShippedConfigs() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kConfigs)) {
    const std::string relative = std::filesystem::relative(entry.path(), kConfigs).string();
    if (entry.path().extension() == ".yaml" && relative.rfind("targets/", 0) != 0) {
      files.push_back(relative);
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

class ResolvedYamlRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(ResolvedYamlRoundTrip, ReadsBackToTheSameConfiguration) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(kConfigs + GetParam(), &config, &why)) << why;
  const std::string resolved = ResolvedYaml(config);
  RunConfig again;
  ASSERT_TRUE(LoadRunConfigFromString(resolved, "resolved.yaml", &again, &why)) << why;
  ASSERT_EQ(again.scenarios.size(), config.scenarios.size());
  EXPECT_EQ(ResolvedYaml(again), resolved);  // A fixed point: nothing lost, nothing added.
  for (size_t i = 0; i < config.scenarios.size(); ++i) {
    EXPECT_TRUE(again.scenarios[i] == config.scenarios[i]) << config.scenarios[i].name;
  }
  // The comparison sees a field that differs (here one the tests never set).
  again.scenarios[0].rendering.render.white_gray += 1;
  EXPECT_FALSE(again.scenarios[0] == config.scenarios[0]);
}

INSTANTIATE_TEST_SUITE_P(Configs, ResolvedYamlRoundTrip, ::testing::ValuesIn(ShippedConfigs()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param.substr(0, param.param.size() - 5);
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// The walk finds the entry points scripts/bench runs (a wrong root would instantiate nothing).
TEST(Config, ShippedConfigsAreFound) {
  const std::vector<std::string> files = ShippedConfigs();
  for (const char* entry :
       {"thesis/all.yaml", "sweeps/noise.yaml", "dynamic/all.yaml", "dynamic/rig_step.yaml"}) {
    EXPECT_NE(std::find(files.begin(), files.end(), entry), files.end()) << entry;
  }
}

TEST(Config, BatchMethodsAndRandomPointsParse) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(
      Scenario("  methods: {dlt: {enabled: true}, ceres: {enabled: true, model: pinhole-k2, "
               "loss: huber}}\n"),
      "test.yaml", &config, &why))
      << why;
  EXPECT_TRUE(config.scenarios[0].FindMethod("dlt")->enabled);
  EXPECT_EQ(MethodOption(config.scenarios[0], "ceres", "model"), "pinhole-k2");
  EXPECT_EQ(MethodOption(config.scenarios[0], "ceres", "loss"), "huber");
  EXPECT_NE(
      LoadError(Scenario("  methods: {ceres: {model: fisheye}}\n")).find("'fisheye' is not one of"),
      std::string::npos);
  EXPECT_NE(LoadError(Scenario("  methods: {bundle: {enabled: true}}\n")).find("unknown key"),
            std::string::npos);
  ASSERT_TRUE(LoadRunConfig(kFixtures + "crlb50.yaml", &config, &why)) << why;
  const ScenarioConfig& s = config.scenarios[0];
  ASSERT_EQ(s.points.xyz.size(), 150u);
  for (const Eigen::Vector3d& p : s.points.xyz) {
    EXPECT_GE(p.y(), 15.0);
    EXPECT_LE(p.y(), 30.0);
  }
  RunConfig again;
  ASSERT_TRUE(LoadRunConfig(kFixtures + "crlb50.yaml", &again, &why));
  EXPECT_EQ(again.scenarios[0].points.xyz, s.points.xyz);  // Drawn from the seed: reproducible.
}

// The rendered-detection configs load, round-trip through the resolved YAML, and the rendered
// switch's misuses are named.
TEST(Config, RenderedScenariosLoadRoundTripAndRefuseMisuse) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(kFixtures + "sim03_rig.yaml", &config, &why)) << why;
  ASSERT_EQ(config.scenarios.size(), 1u);
  const ScenarioConfig& r = config.scenarios[0];
  EXPECT_EQ(r.detections, Detections::kRendered);
  ASSERT_EQ(r.points.aprilgrids.size(), 2u);
  EXPECT_EQ(r.points.xyz.size(), 2u * 4 * 20);
  EXPECT_EQ(r.points.aprilgrids[1].grid.first_id, 20);
  EXPECT_EQ(r.rendering.detection.detector.quad_decimate, 2.0);
  EXPECT_EQ(r.RenderingOptions().frame_rate_hz, 30.0);
  RunConfig again;
  ASSERT_TRUE(LoadRunConfigFromString(ResolvedYaml(config), "resolved.yaml", &again, &why)) << why;
  EXPECT_EQ(ResolvedYaml(again), ResolvedYaml(config));
  EXPECT_EQ(again.scenarios[0].points, r.points);

  EXPECT_NE(LoadError(Scenario("  measurements: {detections: rendered, sample_rate_hz: 30}\n"))
                .find("needs AprilTag targets"),
            std::string::npos);
  const std::string grid =
      "  points: {aprilgrids: [{tag_rows: 2, tag_cols: 2, tag_size_m: 0.1, origin: [0, 3, 0], "
      "rpy_deg: [90, 0, 0]}]}\n";
  EXPECT_NE(LoadError(Scenario("  measurements: {detections: rendered}\n" + grid))
                .find("needs a frame rate"),
            std::string::npos);
  EXPECT_NE(LoadError(Scenario("  measurements: {detections: rendered, sample_rate_hz: 30}\n"
                               "  noise: {pixel_sigma_px: 0.5}\n" +
                               grid))
                .find("take their noise from the image"),
            std::string::npos);
  EXPECT_NE(LoadError(Scenario("  rendering: {supersample: 0}\n")).find("supersample"),
            std::string::npos);
  EXPECT_NE(LoadError(Scenario("  rendering: {detector: {quad_decimat: 2}}\n")).find("unknown key"),
            std::string::npos);
  EXPECT_NE(LoadError(Scenario("  points: {aprilgrids: [{family: tag99h9}]}\n")).find("tag99h9"),
            std::string::npos);
  EXPECT_NE(LoadError(Scenario("  points: {aprilgrids: [{black_tag_border: 3}]}\n"))
                .find("black_tag_border must be 1 (AprilTag 3) or 2 (Kalibr), not 3"),
            std::string::npos);
}

// Scenario aprilgrids keep AprilTag 3's 1-bit border unless they ask for Kalibr's 2-bit one, and
// the resolved YAML says which.
TEST(Config, AprilGridBorderDefaultsToOneBitAndRoundTrips) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(
      Scenario("  points: {aprilgrids: [{tag_rows: 2, tag_cols: 2}, {first_id: 4, "
               "black_tag_border: 2}]}\n"),
      "grids.yaml", &config, &why))
      << why;
  const auto& grids = config.scenarios[0].points.aprilgrids;
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0].grid.black_tag_border, 1);
  EXPECT_EQ(grids[1].grid.black_tag_border, 2);
  EXPECT_NE(ResolvedYaml(config).find("black_tag_border: 2"), std::string::npos);
  RunConfig again;
  ASSERT_TRUE(LoadRunConfigFromString(ResolvedYaml(config), "resolved.yaml", &again, &why)) << why;
  EXPECT_EQ(again.scenarios[0].points.aprilgrids[1].grid.black_tag_border, 2);
}

// Every registered type's options go through the YAML writer and parser unchanged (the type list
// comes from the registry: a new type is covered by being registered).
TEST(Config, EveryMethodTypeRoundTripsThroughTheResolvedYaml) {
  std::string methods = "  methods:\n";
  for (const MethodType& t : MethodTypes()) {
    methods += "    - {name: my_" + t.name + ", type: " + t.name + "}\n";
  }
  RunConfig config, again;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(Scenario(methods), "m.yaml", &config, &why)) << why;
  const ScenarioConfig& s = config.scenarios.at(0);
  ASSERT_EQ(s.methods.size(), MethodTypes().size());
  ASSERT_TRUE(LoadRunConfigFromString(ResolvedYaml(config), "r.yaml", &again, &why)) << why;
  EXPECT_TRUE(again.scenarios.at(0) == s);
  for (size_t i = 0; i < s.methods.size(); ++i) {
    EXPECT_EQ(OptionsKey(*again.scenarios[0].methods[i].method), OptionsKey(*s.methods[i].method))
        << s.methods[i].type;
  }
}

TEST(Config, TruthChangesAreReadWrittenAndRefusedFromTheirDeclaration) {
  const std::string changes =
      "    changes:\n"
      "      - {kind: step, at_s: 2, rpy_deg: [0, 0.5, 0]}\n"
      "      - {kind: ramp, from_s: 3, to_s: 7, fku_px: 4, x_m: [0.01, 0, 0]}\n";
  const std::string truth = "    R_C: [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]\n    x_C: [0, -2, 0.5]\n";
  RunConfig config, again;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(Scenario("", truth + changes), "c.yaml", &config, &why))
      << why;
  const std::vector<CalibrationChange>& read = config.scenarios.at(0).truth_changes;
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].kind, CalibrationChange::Kind::kStep);
  EXPECT_EQ(read[0].from_s, 2.0);  // A step holds its time in both.
  EXPECT_EQ(read[0].to_s, 2.0);
  EXPECT_EQ(read[0].rpy_deg, Eigen::Vector3d(0, 0.5, 0));
  EXPECT_EQ(read[1].kind, CalibrationChange::Kind::kRamp);
  EXPECT_EQ(read[1].from_s, 3.0);
  EXPECT_EQ(read[1].to_s, 7.0);
  EXPECT_EQ(read[1].fku_px, 4.0);
  EXPECT_EQ(read[1].x_m, Eigen::Vector3d(0.01, 0, 0));
  // Written as read: a step with at_s alone, a ramp with from_s and to_s.
  const std::string resolved = ResolvedYaml(config);
  EXPECT_NE(resolved.find("{kind: step, at_s: 2,"), std::string::npos) << resolved;
  EXPECT_NE(resolved.find("{kind: ramp, from_s: 3, to_s: 7,"), std::string::npos) << resolved;
  ASSERT_TRUE(LoadRunConfigFromString(resolved, "r.yaml", &again, &why)) << why;
  EXPECT_TRUE(again.scenarios.at(0) == config.scenarios.at(0));

  const auto error = [&](const std::string& entry) {
    return LoadError(Scenario("", truth + "    changes: [" + entry + "]\n"));
  };
  std::string e = error("{at_s: 2, fku_px: 1}");
  EXPECT_NE(e.find("test.yaml:8:"), std::string::npos) << e;
  EXPECT_NE(e.find("scenario.truth.changes[0].kind: missing"), std::string::npos) << e;
  e = error("{kind: step, fku_px: 1}");
  EXPECT_NE(e.find("scenario.truth.changes[0].at_s: missing (or not a number)"), std::string::npos)
      << e;
  e = error("{kind: ramp, from_s: 1, fku_px: 1}");
  EXPECT_NE(e.find("scenario.truth.changes[0].to_s: missing"), std::string::npos) << e;
  e = error("{kind: step, at_s: 1, to_s: 3, fku_px: 1}");
  EXPECT_NE(e.find("scenario.truth.changes[0].to_s: a step has `at_s`"), std::string::npos) << e;
  e = error("{kind: step, at_s: 1}");
  EXPECT_NE(e.find("scenario.truth.changes[0]: changes nothing"), std::string::npos) << e;
  e = error("{kind: step, at_s: 1, fku_pz: 2}");
  EXPECT_NE(e.find("scenario.truth.changes[0].fku_pz: unknown key (did you mean 'fku_px'?)"),
            std::string::npos)
      << e;
  e = error("{kind: , at_s: 1, fku_px: 1}");  // A null kind is no kind.
  EXPECT_NE(e.find("scenario.truth.changes[0].kind: missing"), std::string::npos) << e;
  e = error("5");
  EXPECT_NE(e.find("scenario.truth.changes[0]: expected a mapping"), std::string::npos) << e;

  // `changes: []` is a value: it clears the changes a base gave.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "calibench_config_test_changes";
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "base.yaml") << Scenario("", truth + changes);
    std::ofstream(dir / "still.yaml")
        << "base: base.yaml\nscenario:\n  name: still\n  truth:\n    changes: []\n";
  }
  ASSERT_TRUE(LoadRunConfig((dir / "still.yaml").string(), &config, &why)) << why;
  EXPECT_TRUE(config.scenarios.at(0).truth_changes.empty());
  std::filesystem::remove_all(dir);
}

TEST(Config, DuplicateScenarioNamesAreRefused) {
  const std::string inline_scenario = "  - {name: a, points: {preset: thesis}}\n";
  const std::string why = LoadError("scenarios:\n" + inline_scenario + inline_scenario);
  EXPECT_NE(why.find("'a' is used by two scenarios"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
