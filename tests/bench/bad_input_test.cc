// The bad-input matrix: every way a user can hand calibench something wrong, and what must come
// back. Each case ends either in a refusal whose message names the file, the line (where the input
// has lines), the field and the reason, or in a result row with status failed / diverged and a
// reason, while the other rows of the run are still produced. Never a crash, never a silent
// number. Runtime faults (trials, images, output) are in bad_run_test.cc.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bench/config/config_io.h"
#include "io/target_io.h"
#include "tests/common/scenario_yaml.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

std::string TempPath(const std::string& name) {
  return (fs::path(testing::TempDir()) / ("bad_input_" + name)).lexically_normal().string();
}

void Write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The minimal scenario (tests/common/scenario_yaml.h) with `extra` lines, `points` and
// `truth_lines` replacing R_C and x_C.
std::string Scenario(const std::string& extra = "", const std::string& points = "",
                     const std::string& truth_lines = "") {
  ScenarioYamlParts parts;
  parts.extra = extra;
  if (!points.empty()) parts.points = points;
  if (!truth_lines.empty()) parts.truth_lines = truth_lines;
  return MinimalScenarioYaml(parts);
}

struct ConfigCase {
  std::string name;
  std::string yaml;
  std::vector<std::string> expected;  // Substrings of the error: location, field, reason.
};

void PrintTo(const ConfigCase& c, std::ostream* os) { *os << c.name; }

class BadConfig : public testing::TestWithParam<ConfigCase> {};

TEST_P(BadConfig, IsRefusedWithFileLineFieldAndReason) {
  const ConfigCase& c = GetParam();
  const std::string path = TempPath(c.name + ".yaml");
  Write(path, c.yaml);
  RunConfig config;
  std::string why;
  ASSERT_FALSE(LoadRunConfig(path, &config, &why)) << c.yaml;
  EXPECT_EQ(why.rfind(path, 0), 0u) << "the message must start with the file: " << why;
  for (const std::string& e : c.expected) {
    const std::string want = e.find("FILE") == 0 ? path + e.substr(4) : e;
    EXPECT_NE(why.find(want), std::string::npos) << "missing '" << want << "' in: " << why;
  }
}

const std::string kFixedCamera = "  case: fixed_camera\n";
// The minimal scenario's R_C and x_C lines (6, 7), for cases that add truth lines after them.
const std::string kTruth = "    R_C: [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]\n    x_C: [0, -2, 0.5]\n";

INSTANTIATE_TEST_SUITE_P(
    Matrix, BadConfig,
    testing::Values(
        ConfigCase{"malformed_flow",
                   "scenario:\n  name: [unclosed\n  trials: 1\n",
                   {"FILE:3:", "malformed YAML", "end of sequence flow not found"}},
        ConfigCase{"malformed_indent",
                   "scenario:\n  name: t\n duration_s: 5\n",
                   {"FILE:3:", "malformed YAML"}},
        ConfigCase{"tab_indent", "scenario:\n\tname: t\n", {"FILE:2:", "malformed YAML"}},
        ConfigCase{"empty_file", "", {"(top level)", "expected a mapping"}},
        ConfigCase{"misspelt_top_key",
                   "scenraio: {name: t}\n",
                   {"FILE:1:", "scenraio", "unknown key", "did you mean 'scenario'"}},
        ConfigCase{"misspelt_gain",
                   Scenario("  methods: {adaptive: {alhpa: 5}}\n"),
                   {"FILE:4:", "scenario.methods.adaptive.alhpa", "did you mean 'alpha'"}},
        ConfigCase{"misspelt_noise",
                   Scenario("  noise: {pixel_sigma: 0.5}\n"),
                   {"FILE:4:", "scenario.noise.pixel_sigma", "did you mean 'pixel_sigma_px'"}},
        ConfigCase{"wrong_type_integer",
                   Scenario("  trials: many\n"),
                   {"FILE:4:", "scenario.trials", "expected an integer, got 'many'"}},
        ConfigCase{"wrong_type_number",
                   Scenario("  noise: {pixel_sigma_px: high}\n"),
                   {"FILE:4:", "scenario.noise.pixel_sigma_px", "expected a number"}},
        ConfigCase{"wrong_type_vector",
                   Scenario("", "{preset: thesis, count: 10}", "    x_C: [0, 1]\n"),
                   {"FILE:6:", "scenario.truth.x_C", "expected a list of 3 numbers"}},
        ConfigCase{"wrong_type_section",
                   Scenario("", "5"),
                   {"FILE:8:", "scenario.points", "expected a mapping"}},
        ConfigCase{"negative_pixel_sigma",
                   Scenario("  noise: {pixel_sigma_px: -0.5}\n"),
                   {"FILE:4:", "scenario.noise", "pixel_sigma_px must be >= 0"}},
        ConfigCase{"negative_point_sigma",
                   Scenario("  noise: {point_sigma_m: -1.0e-3}\n"),
                   {"FILE:4:", "scenario.noise", "point_sigma_m must be >= 0"}},
        ConfigCase{"phi_zero",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {phi_deg: 0}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "phi_deg must lie in (0, 180)"}},
        ConfigCase{"phi_180",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {phi_deg: 180}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "phi_deg must lie in (0, 180)"}},
        ConfigCase{"fisheye_k5",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {lens_family: equidistant, "
                   "k1: 0.01, k5: 0.001}\n",
                   {"FILE:4:", "scenario.truth.intrinsics.k5", "no lens model has k5",
                    "equidistant (fisheye, Kannala-Brandt) model has k1..k4"}},
        ConfigCase{"fisheye_tangential",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {lens_family: equidistant, "
                   "p1: 0.001}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "no tangential terms"}},
        ConfigCase{
            "unknown_lens_family",
            "scenario:\n  name: t\n  truth:\n    intrinsics: {lens_family: omni}\n",
            {"FILE:4:", "scenario.truth.intrinsics.lens_family", "unknown lens family 'omni'"}},
        ConfigCase{"unified_negative_xi",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {lens_family: unified, "
                   "xi: -0.1}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "xi must be >= 0"}},
        ConfigCase{"eucm_alpha_above_1",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {lens_family: eucm, "
                   "alpha: 1.2}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "alpha must lie in [0, 1]"}},
        ConfigCase{"eucm_beta_zero",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {lens_family: eucm, "
                   "alpha: 0.5, beta: 0}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "beta must be > 0"}},
        ConfigCase{"focal_zero",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {fku_px: 0}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "fku_px"}},
        ConfigCase{"focal_negative",
                   "scenario:\n  name: t\n  truth:\n    intrinsics: {fkv_px: -810}\n",
                   {"FILE:4:", "scenario.truth.intrinsics", "fkv_px"}},
        ConfigCase{"zero_trials",
                   Scenario("  trials: 0\n"),
                   {"FILE:4:", "scenario.trials", "must be >= 1"}},
        ConfigCase{"trials_beyond_int",
                   Scenario("  trials: 1000000000000\n"),
                   {"FILE:4:", "scenario.trials", "at most 1000000"}},
        ConfigCase{"duration_zero",
                   "scenario:\n  name: t\n  duration_s: 0\n",
                   {"FILE:3:", "scenario.duration_s", "must be positive and finite"}},
        ConfigCase{"duration_infinite",
                   "scenario:\n  name: t\n  duration_s: .inf\n",
                   {"FILE:3:", "scenario.duration_s", "must be positive and finite"}},
        ConfigCase{"frames_beyond_memory",
                   Scenario("  measurements: {sample_rate_hz: 1.0e12}\n"),
                   {"scenario.measurements.sample_rate_hz", "frames", "more than 1e+07"}},
        ConfigCase{"alpha_nan",
                   Scenario("  methods: {adaptive: {alpha: .nan}}\n"),
                   {"FILE:4:", "scenario.methods.adaptive", "alpha must be a positive finite"}},
        ConfigCase{"improper_rotation",
                   Scenario("", "{preset: thesis, count: 10}",
                            "    R_C: [[0, 1, 0], [0, 0, 1], [-1, 0, 0]]\n"),
                   {"FILE:6:", "scenario.truth.R_C", "rotation is improper"}},
        ConfigCase{"non_orthonormal_rotation",
                   Scenario("", "{preset: thesis, count: 10}",
                            "    R_C: [[1, 0.001, 0], [0, 1, 0], [0, 0, 1]]\n"),
                   {"FILE:6:", "scenario.truth.R_C", "not orthonormal"}},
        ConfigCase{"image_size_zero",
                   Scenario("  image_size: [0, 480]\n"),
                   {"FILE:4:", "scenario.image_size", "must be positive"}},
        ConfigCase{"thesis_preset_count",
                   Scenario("", "{preset: thesis, count: 100000000}"),
                   {"FILE:8:", "scenario.points.count", "1 to 10 points"}},
        ConfigCase{"tag_bias_without_tags",
                   Scenario("  diagnostics: {tag_radial_bias_px: 0.01}\n"),
                   {"scenario.diagnostics.tag_radial_bias_px", "AprilGrids only"}},
        ConfigCase{"random_phase_not_bool",
                   Scenario("  motion: {preset: small, random_phase: maybe}\n"),
                   {"scenario.motion.random_phase"}},
        ConfigCase{"rendered_without_tags",
                   Scenario("  measurements: {detections: rendered, sample_rate_hz: 10}\n"),
                   {"scenario.points", "detections: rendered needs AprilTag targets"}},
        ConfigCase{"misspelt_detections",
                   Scenario("  measurements: {detections: renderd}\n"),
                   {"FILE:4:", "scenario.measurements.detections",
                    "'renderd' is not one of: oracle, rendered", "did you mean 'rendered'"}},
        ConfigCase{"misspelt_outside_image",
                   Scenario("  measurements: {outside_image: keeep}\n"),
                   {"FILE:4:", "scenario.measurements.outside_image", "did you mean 'keep'"}},
        ConfigCase{
            "motion_preset_and_components",
            Scenario("  motion: {preset: small, v_const: [0, 0, 1]}\n"),
            {"FILE:4:", "scenario.motion.v_const", "give either a preset or the components"}},
        ConfigCase{"unknown_corner_error_part",
                   Scenario("  diagnostics: {corner_error_part: z}\n"),
                   {"FILE:4:", "scenario.diagnostics.corner_error_part", "unknown part 'z'",
                    "all, x, y, tag_translation, tag_shape"}},
        ConfigCase{"corner_error_grid_below_minus_one",
                   Scenario("  diagnostics: {corner_error_grid: -2}\n"),
                   {"scenario.diagnostics.corner_error_grid", "a grid's index"}},
        ConfigCase{"corner_error_grid_past_the_grids",
                   "base: " + std::string(CALIBENCH_SOURCE_DIR) +
                       "/tests/fixtures/rig.yaml\nscenario:\n  measurements: {detections: "
                       "rendered}\n  noise: {pixel_sigma_px: 0}\n  diagnostics: "
                       "{corner_error_grid: 2}\n",
                   {"scenario.diagnostics.corner_error_grid", "2 names no grid",
                    "the scenario has 2 aprilgrids"}},
        ConfigCase{"corner_error_on_oracle",
                   Scenario("  diagnostics: {corner_error_clip_px: 0}\n"),
                   {"scenario.diagnostics", "need detections: rendered"}},
        ConfigCase{"missing_base",
                   "base: nowhere.yaml\nscenario: {name: x}\n",
                   {"FILE:1:7: base: cannot open '", "nowhere.yaml'"}},
        ConfigCase{"sweep_empty_values",
                   Scenario() + "sweep:\n  - field: noise.pixel_sigma_px\n    values: []\n",
                   {"FILE:11:", "sweep[0].values", "expected a non-empty list"}},
        ConfigCase{
            "sweep_bad_value",
            Scenario() + "sweep:\n  - field: methods.adaptive.alpha\n    values: [10]\n"
                         "  - field: noise.pixel_sigma_px\n    values: [0.5, -1]\n",
            {"FILE:13:19: sweep point", "noise.pixel_sigma_px=-1", "pixel_sigma_px must be >= 0"}},
        ConfigCase{
            "sweep_bad_range_value",
            Scenario() + "sweep:\n  - field: noise.pixel_sigma_px\n"
                         "    range: {from: -1, to: 0, step: 1}\n",
            {"FILE:11:12: sweep point", "noise.pixel_sigma_px=-1", "pixel_sigma_px must be >= 0"}},
        ConfigCase{"sweep_error_not_the_sweeps",
                   Scenario("", "", kTruth + "    changes: [{kind: step, at_s: 60, fku_px: 1}]\n") +
                       "sweep:\n  - field: noise.pixel_sigma_px\n    values: [0.5]\n",
                   {"FILE:8:15:", ".truth.changes[0]", "at_s = 60 s is outside the run [0, 10] s"}},
        ConfigCase{"sweep_bad_second_grid",
                   Scenario("",
                            "{aprilgrids: [{tag_rows: 2, tag_cols: 2, tag_size_m: 0.1, origin: "
                            "[0, 3, 0], rpy_deg: [90, 0, 0]}, {tag_rows: 2, tag_cols: 2, "
                            "tag_size_m: 0.1, first_id: 4, origin: [0.5, 3, 0], rpy_deg: [90, 0, "
                            "0]}]}") +
                       "sweep:\n  - field: points.aprilgrids.0.tag_size_m\n    values: [0.1]\n"
                       "  - field: points.aprilgrids.1.tag_size_m\n    values: [-1]\n",
                   {"FILE:13:14: sweep point", "aprilgrids[1]", "tag_size_m must be positive"}},
        ConfigCase{"sweep_unknown_field",
                   Scenario() + "sweep:\n  - field: noise.pixel_sigmaa\n    values: [1]\n",
                   {"noise.pixel_sigmaa", "unknown key"}},
        // Method instances.
        ConfigCase{"unknown_method_type",
                   Scenario("  methods:\n    - {name: x, type: bundle_adjust}\n"),
                   {"FILE:5:", "scenario.methods[0].type", "unknown method type 'bundle_adjust'",
                    "registered types: adaptive, dlt, zhang, zhang_handeye, ceres"}},
        ConfigCase{"duplicate_instance_name",
                   Scenario("  methods:\n    - {name: a, type: adaptive}\n"
                            "    - {name: a, type: ceres}\n"),
                   {"FILE:6:", "scenario.methods[1].name", "'a' is already the name of",
                    "scenario.methods[0]"}},
        ConfigCase{"instance_without_type",
                   Scenario("  methods:\n    - {name: a, alpha: 100}\n"),
                   {"FILE:5:", "scenario.methods[0]", "missing 'type'"}},
        ConfigCase{"instance_option_of_another_type",
                   Scenario("  methods:\n    - {name: a, type: dlt, alpha: 100}\n"),
                   {"FILE:5:", "scenario.methods[0].alpha", "unknown key",
                    "allowed: name, type, enabled, convergence_tol, min_planarity_ratio"}},
        ConfigCase{"init_names_nothing",
                   Scenario("  methods:\n    - {name: c, type: ceres, init: nope}\n"),
                   {"scenario.methods.c", "'nope' is neither a method instance"}},
        ConfigCase{"sweep_missing_instance",
                   Scenario("  methods:\n    - {name: a100, type: adaptive}\n") +
                       "sweep:\n  - field: methods.a1000.alpha\n    values: [1, 2]\n",
                   {"FILE:12:", "sweep[0].field", "no method instance named 'a1000'",
                    "its instances: a100"}},
        ConfigCase{"image_size_absurd",
                   Scenario("  image_size: [100000, 100000]\n  measurements: {detections: "
                            "rendered, sample_rate_hz: 10}\n",
                            "{aprilgrids: [{tag_rows: 2, tag_cols: 2, tag_size_m: 0.1, origin: "
                            "[0, 3, 0], rpy_deg: [90, 0, 0]}]}"),
                   {"FILE:4:", "scenario.image_size", "[100000, 100000] px is larger than",
                    "16384 px per side", "MiB"}},
        ConfigCase{"board_corners_past_the_bound",  // 10000 x 10000 corners: 2.4 GB of points.
                   Scenario("", "{boards: [{rows: 10000, cols: 10000, spacing_m: 0.01}]}"),
                   {"scenario.points.boards", "100000000 corners",
                    "a scenario has at most 100000 points"}},
        ConfigCase{"board_side_past_the_bound",
                   Scenario("", "{boards: [{rows: 2, cols: 60000, spacing_m: 0.01}]}"),
                   {"at most 10000 corners a side"}},
        ConfigCase{"grid_past_its_family",
                   Scenario("", "{aprilgrids: [{tag_rows: 30, tag_cols: 30, tag_size_m: 0.1}]}"),
                   {"tag36h11 has 587 codes", "30 x 30 tags from id 0 need ids up to 899"}},
        // Dynamic calibration.
        ConfigCase{
            "change_after_the_run",
            Scenario("", "",
                     kTruth + "    changes: [{kind: step, at_s: 60, rpy_deg: [0, 0.5, 0]}]\n"),
            {"FILE:8:", "scenario.truth.changes[0]", "at_s = 60 s is outside the run [0, 10] s"}},
        ConfigCase{
            "change_before_the_run",
            Scenario("", "",
                     kTruth + "    changes: [{kind: ramp, from_s: -1, to_s: 5, fku_px: 2}]\n"),
            {"FILE:8:", "scenario.truth.changes[0]", "from_s = -1 s is outside the run"}},
        ConfigCase{
            "overlapping_ramps",
            Scenario("", "",
                     kTruth + "    changes:\n      - {kind: ramp, from_s: 1, to_s: 6, fku_px: 2}\n"
                              "      - {kind: ramp, from_s: 5, to_s: 9, fku_px: 1}\n"),
            {"scenario.truth.changes", "changes[0] and changes[1] both ramp fku_px",
             "overlapping intervals [1, 6] and [5, 9] s"}},
        ConfigCase{
            "misspelt_change_kind",
            Scenario("", "",
                     kTruth + "    changes: [{kind: stpe, at_s: 5, rpy_deg: [0, 0.5, 0]}]\n"),
            {"FILE:8:", "scenario.truth.changes[0].kind", "'stpe' is not one of: step, ramp",
             "did you mean 'step'"}},
        ConfigCase{
            "nan_delta",
            Scenario("", "",
                     kTruth + "    changes: [{kind: step, at_s: 5, rpy_deg: [0, .nan, 0]}]\n"),
            {"FILE:8:", "scenario.truth.changes[0]", "every delta must be finite"}},
        ConfigCase{
            "negative_window",
            Scenario("  methods: {ceres: {enabled: true, window_s: -2}}\n"),
            {"FILE:4:", "scenario.methods.ceres", "window_s must be >= 0 (0: static) or all"}},
        ConfigCase{"every_zero",
                   Scenario("  methods: {dlt: {enabled: true, window_s: 5, every_s: 0}}\n"),
                   {"FILE:4:", "scenario.methods.dlt", "every_s must be a positive number"}},
        ConfigCase{"negative_forgetting",
                   Scenario("  methods: {adaptive: {forgetting_beta: -0.1}}\n"),
                   {"FILE:4:", "scenario.methods.adaptive", "forgetting_beta must be >= 0"}},
        ConfigCase{"reset_threshold_above_gamma0",
                   Scenario("  methods: {adaptive: {gamma0: 1, reset_threshold: 2}}\n"),
                   {"FILE:4:", "scenario.methods.adaptive", "reset_threshold must lie in [0, 1)"}},
        ConfigCase{"duplicate_names",
                   "scenarios:\n  - " + std::string("{name: a, points: {preset: thesis}}\n") +
                       "  - {name: a, points: {preset: thesis}}\n",
                   {"scenario.name", "'a' is used by two scenarios"}}),
    [](const testing::TestParamInfo<ConfigCase>& param_info) { return param_info.param.name; });

TEST(BadConfigFile, CycleDirectoryAndDevicesAreRefused) {
  const std::string self = TempPath("self_base.yaml");
  Write(self, "base: bad_input_self_base.yaml\nscenario: {name: x}\n");
  RunConfig config;
  std::string why;
  EXPECT_FALSE(LoadRunConfig(self, &config, &why));
  EXPECT_NE(why.find(self + ":1:7: base: nesting deeper than 16 (a cycle?)"), std::string::npos)
      << why;

  const std::string dir = TempPath("dir.yaml");
  fs::create_directories(dir);
  EXPECT_FALSE(LoadRunConfig(dir, &config, &why));
  EXPECT_NE(why.find(dir + ": (file): not a regular file"), std::string::npos) << why;

  // `base: /dev/zero` would otherwise read forever.
  const std::string device = TempPath("device_base.yaml");
  Write(device, "base: /dev/zero\nscenario: {name: x}\n");
  EXPECT_FALSE(LoadRunConfig(device, &config, &why));
  EXPECT_NE(why.find("/dev/zero: (file): not a regular file"), std::string::npos) << why;
}

TEST(BadTarget, KalibrTargetYamlErrorsNameLineFieldReason) {
  struct Case {
    std::string name, yaml, expected;
  };
  const Case cases[] = {
      {"unknown_type", "target_type: 'circlegrid'\n",
       ":1:14: target_type: 'circlegrid' is not one of: aprilgrid, checkerboard"},
      {"misspelt_key",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacng: 0.3\n",
       ":5:1: tagSpacng: unknown key (did you mean 'tagSpacing'?)"},
      {"negative_cols",
       "target_type: aprilgrid\ntagCols: -3\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n",
       ":2:10: tagCols: must be >= 1"},
      {"zero_tag_size",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0\ntagSpacing: 0.3\n",
       ":4:10: tagSize: must be > 0"},
      {"negative_tag_size",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: -0.088\ntagSpacing: 0.3\n",
       ":4:10: tagSize: must be > 0"},
      {"negative_tag_spacing",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: -0.3\n",
       ":5:13: tagSpacing: must be > 0"},
      {"zero_border",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n"
       "blackTagBorder: 0\n",
       ":6:17: blackTagBorder: must be 1 (AprilTag 3's layout) or 2"},
      {"wide_border",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n"
       "blackTagBorder: 3\n",
       ":6:17: blackTagBorder: must be 1"},
      {"border_of_a_reversed_family",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n"
       "tagFamily: tagStandard41h12\nblackTagBorder: 2\n",
       ":7:17: blackTagBorder: tagStandard41h12 has a white (reversed) border"},
      {"zero_spacing",
       "target_type: checkerboard\ntargetCols: 9\ntargetRows: 6\nrowSpacingMeters: 0\n"
       "colSpacingMeters: 0.02\n",
       "rowSpacingMeters: spacings must be > 0"},
      {"unknown_family",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n"
       "tagFamily: tag99h9\n",
       ":6:12: tagFamily: 'tag99h9' is not one of"},
      // Ids past the family's codes; the first case's tag count overflows an int (found by the
      // target YAML fuzzer).
      {"tags_past_int",
       "target_type: aprilgrid\ntagCols: 67777777\ntagRows: 9\ntagSize: 0.1\ntagSpacing: 0.3\n",
       ":3:10: tagRows x tagCols: tag36h11 has 587 codes (ids 0..586): 9 x 67777777 tags from id 0 "
       "need ids up to 609999992"},
      {"tags_past_the_family",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n"
       "tagFamily: tag25h9\n",
       ":3:10: tagRows x tagCols: tag25h9 has 35 codes (ids 0..34): 6 x 6 tags from id 0 need ids "
       "up to 35"},
      {"offset_past_the_family",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n"
       "codeOffset: 2147483600\n",
       "tag36h11 has 587 codes (ids 0..586): 6 x 6 tags from id 2147483600 need ids up to "
       "2147483635"},
      {"negative_offset",
       "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.1\ntagSpacing: 0.3\n"
       "codeOffset: -1\n",
       ":6:13: codeOffset: must be >= 0"},
      {"huge_checkerboard",
       "target_type: checkerboard\ntargetCols: 9\ntargetRows: 20000\nrowSpacingMeters: 0.02\n"
       "colSpacingMeters: 0.02\n",
       ":3:13: targetRows: at most 10000 inner corners a side"},
  };
  for (const Case& c : cases) {
    const std::string path = TempPath("target_" + c.name + ".yaml");
    Write(path, c.yaml);
    CalibrationTarget target;
    std::string why;
    EXPECT_FALSE(LoadTargetYaml(path, &target, &why)) << c.name;
    EXPECT_EQ(why.rfind(path, 0), 0u) << why;
    EXPECT_NE(why.find(c.expected), std::string::npos) << c.name << ": " << why;
  }
}

}  // namespace
}  // namespace calibench
