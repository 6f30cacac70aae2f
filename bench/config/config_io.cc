#include "bench/config/config_io.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bench/config/config_parsers.h"
#include "bench/config/yaml_reader.h"
#include "core/random.h"
#include "core/synthetic.h"
#include "metrics/tracking.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;
using config_internal::ConfigError;
using config_internal::ParseCamera;
using config_internal::Reader;

void ParsePoints(const Reader& r, const YAML::Node& node, const std::string& field,
                 ScenarioConfig* s) {
  r.CheckKeys(node, field, {"preset", "count", "list", "random", "boards", "aprilgrids"});
  const bool has_preset = node["preset"].IsDefined();
  const bool has_list = node["list"].IsDefined();
  const bool has_random = node["random"].IsDefined();
  const bool has_boards = node["boards"].IsDefined();
  const bool has_grids = node["aprilgrids"].IsDefined();
  if (has_preset + has_list + has_random + has_boards + has_grids != 1) {
    r.Fail(node, field, "give exactly one of 'preset', 'list', 'random', 'boards' or 'aprilgrids'");
  }
  s->points.clear();
  s->points_preset.clear();
  s->boards.clear();
  s->aprilgrids.clear();
  s->board_rpy_deg.clear();
  s->aprilgrid_rpy_deg.clear();
  if (has_grids) {
    const YAML::Node list = node["aprilgrids"];
    const std::string f = Reader::Join(field, "aprilgrids");
    if (!list.IsSequence() || list.size() == 0) r.Fail(list, f, "expected a non-empty list");
    for (size_t i = 0; i < list.size(); ++i) {
      AprilGrid g;
      Eigen::Vector3d rpy_deg;
      config_internal::ParseAprilGrid(r, list[i], f + "[" + std::to_string(i) + "]", &g, &rpy_deg);
      s->aprilgrid_rpy_deg.push_back(rpy_deg);
      const std::vector<Eigen::Vector3d> corners = g.CornersInPointsFrame();
      s->points.insert(s->points.end(), corners.begin(), corners.end());
      s->aprilgrids.push_back(g);
    }
    s->points_preset = "aprilgrids";
    s->points_count = static_cast<int>(s->points.size());
    return;
  }
  if (has_boards) {
    const YAML::Node list = node["boards"];
    const std::string f = Reader::Join(field, "boards");
    if (!list.IsSequence() || list.size() == 0) r.Fail(list, f, "expected a non-empty list");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string bf = f + "[" + std::to_string(i) + "]";
      r.CheckKeys(list[i], bf, {"rows", "cols", "spacing_m", "origin", "rpy_deg"});
      PlanarBoard b;
      r.If(list[i], "rows", bf, [&](auto n, auto g) { b.rows = r.Int(n, g); });
      r.If(list[i], "cols", bf, [&](auto n, auto g) { b.cols = r.Int(n, g); });
      r.If(list[i], "spacing_m", bf, [&](auto n, auto g) { b.spacing_m = r.Double(n, g); });
      r.If(list[i], "origin", bf,
           [&](auto n, auto g) { b.points_from_board.translation = r.Vector3(n, g); });
      Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
      r.If(list[i], "rpy_deg", bf, [&](auto n, auto g) {
        rpy_deg = r.Vector3(n, g);
        b.points_from_board.rotation = FromRollPitchYawDeg(rpy_deg);
      });
      std::string why;
      if (!b.Check(&why)) r.Fail(list[i], bf, why);
      s->boards.push_back(b);
      s->board_rpy_deg.push_back(rpy_deg);
    }
    s->points_preset = "boards";
    s->points = RigCorners(s->boards);
    s->points_count = static_cast<int>(s->points.size());
    return;
  }
  if (has_random) {
    const YAML::Node rnd = node["random"];
    const std::string f = Reader::Join(field, "random");
    r.CheckKeys(rnd, f, {"count", "min", "max"});
    for (const char* key : {"count", "min", "max"}) {
      if (!rnd[key].IsDefined()) r.Fail(rnd, Reader::Join(f, key), "missing");
    }
    const long count = r.Integer(rnd["count"], f + ".count");
    if (count < 1 || count > 100000) r.Fail(rnd["count"], f + ".count", "must lie in [1, 100000]");
    s->points_preset = "random";
    s->points_count = static_cast<int>(count);
    s->random_min = r.Vector3(rnd["min"], f + ".min");
    s->random_max = r.Vector3(rnd["max"], f + ".max");
    if (!(s->random_min.array() < s->random_max.array()).all()) {
      r.Fail(rnd, f, "min must be below max in every coordinate");
    }
    return;  // Drawn from the seed once the whole scenario is read (see Finish).
  }
  if (has_preset) {
    s->points_preset = r.Choice(node["preset"], Reader::Join(field, "preset"), {"thesis"});
    s->points_count = 10;
    r.If(node, "count", field, [&](auto n, auto f) {
      const long count = r.Integer(n, f);
      if (count < 1 || count > 10)
        r.Fail(n, f, "the thesis preset has 1 to 10 points, got " + std::to_string(count));
      s->points_count = static_cast<int>(count);
    });
    s->points = ThesisFeaturePoints(s->points_count);
    return;
  }
  if (node["count"].IsDefined()) r.Fail(node["count"], field + ".count", "only with a preset");
  const YAML::Node list = node["list"];
  const std::string list_field = Reader::Join(field, "list");
  if (!list.IsSequence() || list.size() == 0) {
    r.Fail(list, list_field, "expected a non-empty list of [x, y, z] points");
  }
  for (size_t i = 0; i < list.size(); ++i) {
    s->points.push_back(r.Vector3(list[i], list_field + "[" + std::to_string(i) + "]"));
  }
  s->points_count = static_cast<int>(s->points.size());
}

void ParseMotion(const Reader& r, const YAML::Node& node, const std::string& field,
                 ScenarioConfig* s) {
  r.CheckKeys(node, field,
              {"preset", "v_const", "v_cos", "v_sin", "w_const", "w_cos", "w_sin",
               "frequency_rad_s", "frame", "random_phase"});
  s->motion = TwistProfile();
  s->motion_random_phase = false;
  r.Set(node, "random_phase", field, &s->motion_random_phase);
  s->motion_preset.clear();
  if (node["preset"].IsDefined()) {
    for (const char* key :
         {"v_const", "v_cos", "v_sin", "w_const", "w_cos", "w_sin", "frequency_rad_s", "frame"}) {
      if (node[key].IsDefined()) {
        r.Fail(node[key], Reader::Join(field, key), "give either a preset or the components");
      }
    }
    s->motion_preset =
        r.Choice(node["preset"], Reader::Join(field, "preset"), ThesisMotionPresetNames());
    s->motion = *ThesisMotionPreset(s->motion_preset, s->calibration_case);
    return;
  }
  TwistProfile& m = s->motion;
  r.Set(node, "v_const", field, &m.v_const);
  r.Set(node, "v_cos", field, &m.v_cos);
  r.Set(node, "v_sin", field, &m.v_sin);
  r.Set(node, "w_const", field, &m.w_const);
  r.Set(node, "w_cos", field, &m.w_cos);
  r.Set(node, "w_sin", field, &m.w_sin);
  r.Set(node, "frequency_rad_s", field, &m.frequency_rad_s);
  std::string frame = "auto";
  r.If(node, "frame", field, [&](auto n, auto f) {
    frame = r.Choice(n, f, {"auto", "body", "world"});
  });
  const bool fixed = s->calibration_case == CalibrationCase::kFixedCamera;
  m.frame = frame == "world" || (frame == "auto" && fixed) ? TwistProfile::Frame::kWorld
                                                           : TwistProfile::Frame::kBody;
  std::string why;
  if (!m.Check(&why)) r.Fail(node, field, why);
}

// truth.changes: [{kind: step, at_s, ...} | {kind: ramp, from_s, to_s, ...}] (core/scene.h).
void ParseChanges(const Reader& r, const YAML::Node& node, const std::string& field,
                  ScenarioConfig* s) {
  if (!node.IsSequence()) r.Fail(node, field, "expected a list of {kind: step | ramp, ...}");
  s->truth_changes.clear();
  s->truth_change_marks.clear();
  for (size_t i = 0; i < node.size(); ++i) {
    const YAML::Node e = node[i];
    const std::string f = field + "[" + std::to_string(i) + "]";
    r.ExpectMap(e, f);
    if (!e["kind"].IsDefined()) r.Fail(e, f + ".kind", "missing: step or ramp");
    CalibrationChange c;
    const bool step = r.Choice(e["kind"], f + ".kind", {"step", "ramp"}) == "step";
    c.kind = step ? CalibrationChange::Kind::kStep : CalibrationChange::Kind::kRamp;
    std::vector<std::string> keys = {"kind",   "rpy_deg", "x_m",   "fku_px",
                                     "fkv_px", "u0_px",   "v0_px", "phi_deg"};
    const std::vector<std::string> times =
        step ? std::vector<std::string>{"at_s"} : std::vector<std::string>{"from_s", "to_s"};
    keys.insert(keys.end(), times.begin(), times.end());
    r.CheckKeys(e, f, keys);
    for (const std::string& t : times) {
      if (!e[t].IsDefined()) r.Fail(e, f + "." + t, "missing");
    }
    if (step) {
      c.from_s = c.to_s = r.Double(e["at_s"], f + ".at_s");
    } else {
      c.from_s = r.Double(e["from_s"], f + ".from_s");
      c.to_s = r.Double(e["to_s"], f + ".to_s");
    }
    r.Set(e, "rpy_deg", f, &c.rpy_deg);
    r.Set(e, "x_m", f, &c.x_m);
    r.Set(e, "fku_px", f, &c.fku_px);
    r.Set(e, "fkv_px", f, &c.fkv_px);
    r.Set(e, "u0_px", f, &c.u0_px);
    r.Set(e, "v0_px", f, &c.v0_px);
    r.Set(e, "phi_deg", f, &c.phi_deg);
    std::string why;
    // The times are checked against the scenario's duration once it is known (Finish).
    if (!c.Check(std::numeric_limits<double>::infinity(), &why)) r.Fail(e, f, why);
    s->truth_changes.push_back(c);
    std::ostringstream mark;
    mark << r.file() << ":" << e.Mark().line + 1 << ":" << e.Mark().column + 1;
    s->truth_change_marks.push_back(mark.str());
  }
}

// tracking: {enabled, report_rate_hz, band_samples, steady_fraction, tolerance: {QUANTITY: tol}}.
void ParseTracking(const Reader& r, const YAML::Node& node, const std::string& field,
                   TrackingConfig* t) {
  r.CheckKeys(node, field,
              {"enabled", "report_rate_hz", "band_samples", "steady_fraction", "tolerance"});
  r.Set(node, "enabled", field, &t->enabled);
  r.Set(node, "report_rate_hz", field, &t->report_rate_hz);
  r.Set(node, "band_samples", field, &t->band_samples);
  r.Set(node, "steady_fraction", field, &t->metrics.steady_fraction);
  r.If(node, "tolerance", field, [&](auto n, auto f) {
    const auto& names = TrackQuantityNames();
    r.CheckKeys(n, f, std::vector<std::string>(names.begin(), names.end()));
    for (int q = 0; q < kTrackQuantities; ++q) r.Set(n, names[q], f, &t->metrics.tolerance[q]);
  });
  std::string why;
  if (!t->Check(&why)) r.Fail(node, field, why);
}

void ParseReference(const Reader& r, const YAML::Node& node, const std::string& field,
                    Reference* ref) {
  r.CheckKeys(node, field,
              {"source", "method", "fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px", "x_C",
               "theta_err_below"});
  *ref = Reference();
  r.Set(node, "source", field, &ref->source);
  r.Set(node, "method", field, &ref->method);
  r.Set(node, "fku_px", field, &ref->fku_px);
  r.Set(node, "fkv_px", field, &ref->fkv_px);
  r.Set(node, "phi_deg", field, &ref->phi_deg);
  r.Set(node, "u0_px", field, &ref->u0_px);
  r.Set(node, "v0_px", field, &ref->v0_px);
  r.Set(node, "x_C", field, &ref->x_c);
  r.Set(node, "theta_err_below", field, &ref->theta_err_below);
}

// Applies the scenario mapping `node` onto *s (fields absent from `node` keep their values).
void ParseScenario(const Reader& r, const YAML::Node& node, const std::string& field,
                   ScenarioConfig* s) {
  r.CheckKeys(node, field,
              {"name", "description", "case", "duration_s", "seed", "paired_sweep", "trials",
               "truth", "image_size", "points", "motion", "measurements", "noise", "rendering",
               "methods", "tracking", "reference", "sweep_point", "report"});
  r.If(node, "image_size", field, [&](auto n, auto f) {
    if (!n.IsSequence() || n.size() != 2) r.Fail(n, f, "expected [width, height]");
    s->image_width = r.Int(n[0], f + "[0]");
    s->image_height = r.Int(n[1], f + "[1]");
    if (s->image_width < 1 || s->image_height < 1) r.Fail(n, f, "must be positive");
    if (s->image_width > kMaxImageSide || s->image_height > kMaxImageSide ||
        static_cast<double>(s->image_width) * s->image_height > kMaxImagePixels) {
      r.Fail(n, f,
             "[" + std::to_string(s->image_width) + ", " + std::to_string(s->image_height) +
                 "] px is larger than any camera calibrated here (at most " +
                 std::to_string(kMaxImageSide) + " px per side and " +
                 std::to_string(static_cast<int>(kMaxImagePixels / 1e6)) +
                 " Mpx; the renderer's ray table alone would need " +
                 std::to_string(static_cast<long>(16.0 * (s->image_width + 1.0) *
                                                  (s->image_height + 1.0) / (1 << 20))) +
                 " MiB)");
    }
  });
  r.Set(node, "name", field, &s->name);
  r.Set(node, "description", field, &s->description);
  r.If(node, "case", field, [&](auto n, auto f) {
    s->calibration_case = r.Choice(n, f, {"fixed_camera", "moving_camera"}) == "fixed_camera"
                              ? CalibrationCase::kFixedCamera
                              : CalibrationCase::kMovingCamera;
    // A preset motion inherited from a base follows the case.
    if (!s->motion_preset.empty()) {
      s->motion = *ThesisMotionPreset(s->motion_preset, s->calibration_case);
    }
  });
  r.If(node, "duration_s", field, [&](auto n, auto f) {
    s->duration_s = r.Double(n, f);
    if (!(s->duration_s > 0 && std::isfinite(s->duration_s))) {
      r.Fail(n, f, "must be positive and finite");
    }
  });
  r.If(node, "seed", field, [&](auto n, auto f) { s->seed = r.Unsigned(n, f); });
  r.Set(node, "paired_sweep", field, &s->paired_sweep);
  r.If(node, "trials", field, [&](auto n, auto f) {
    const long trials = r.Integer(n, f);
    if (trials < 1) r.Fail(n, f, "must be >= 1, got " + std::to_string(trials));
    if (trials > kMaxTrials) {
      r.Fail(n, f, "at most " + std::to_string(kMaxTrials) + " per scenario (split the seeds)");
    }
    s->trials = static_cast<int>(trials);
  });
  r.If(node, "truth", field, [&](auto n, auto f) {
    ParseCamera(r, n, f, &s->truth, {"changes"});
    r.If(n, "changes", f, [&](auto m, auto g) { ParseChanges(r, m, g, s); });
  });
  r.If(node, "tracking", field, [&](auto n, auto f) { ParseTracking(r, n, f, &s->tracking); });
  r.If(node, "points", field, [&](auto n, auto f) { ParsePoints(r, n, f, s); });
  r.If(node, "motion", field, [&](auto n, auto f) { ParseMotion(r, n, f, s); });
  r.If(node, "measurements", field, [&](auto n, auto f) {
    r.CheckKeys(n, f, {"detections", "sample_rate_hz", "eval_rate_hz", "outside_image"});
    r.If(n, "detections", f, [&](auto m, auto g) {
      s->detections = r.Choice(m, g, {"oracle", "rendered"});
    });
    r.If(n, "outside_image", f, [&](auto m, auto g) {
      s->outside_image = r.Choice(m, g, {"fail", "keep"});
    });
    r.Set(n, "sample_rate_hz", f, &s->measurements.sample_rate_hz);
    r.Set(n, "eval_rate_hz", f, &s->measurements.eval_rate_hz);
    std::string why;
    OracleOptions check = s->measurements;
    check.noise = NoiseOptions();
    if (!check.Check(&why)) r.Fail(n, f, why);
  });
  r.If(node, "noise", field, [&](auto n, auto f) {
    r.CheckKeys(n, f,
                {"point_sigma_m", "pixel_sigma_px", "hold_s", "hold_frames", "tag_radial_bias_px"});
    NoiseOptions& noise = s->measurements.noise;
    r.Set(n, "point_sigma_m", f, &noise.point_sigma_m);
    r.Set(n, "pixel_sigma_px", f, &noise.pixel_sigma_px);
    r.Set(n, "hold_s", f, &noise.hold_s);
    r.Set(n, "hold_frames", f, &noise.hold_frames);
    r.Set(n, "tag_radial_bias_px", f, &noise.tag_radial_bias_px);
    std::string why;
    if (!noise.Check(&why)) r.Fail(n, f, why);
  });
  r.If(node, "rendering", field,
       [&](auto n, auto f) { config_internal::ParseRendering(r, n, f, &s->rendering); });
  r.If(node, "methods", field, [&](auto n, auto f) { config_internal::ParseMethods(r, n, f, s); });
  r.If(node, "reference", field, [&](auto n, auto f) { ParseReference(r, n, f, &s->reference); });
  r.If(node, "report", field, [&](auto n, auto f) {
    r.CheckKeys(n, f, {"role"});
    r.If(n, "role", f, [&](auto m, auto g) { s->report.role = r.Choice(m, g, ReportRoles()); });
  });
  r.If(node, "sweep_point", field, [&](auto n, auto f) {  // Written by ResolvedYaml.
    r.CheckKeys(n, f, {"sweep", "index", "measurement_index", "params"});
    SweepPoint& p = s->sweep_point;
    r.Set(n, "sweep", f, &p.sweep);
    r.Set(n, "index", f, &p.index);
    r.Set(n, "measurement_index", f, &p.measurement_index);
    r.Set(n, "params", f, &p.params);
  });
}

using config_internal::LoadYaml;
using config_internal::ReadFile;

void LoadNode(const YAML::Node& root, const std::string& path, int depth, RunConfig* config);

void LoadFile(const std::string& path, int depth, RunConfig* config) {
  if (depth > 16) throw ConfigError(path + ": (include): nesting deeper than 16 (a cycle?)");
  LoadNode(LoadYaml(ReadFile(path), path), path, depth, config);
}

// Loads the scenario of a scenario file (following `base:`) into *s.
void LoadScenarioFile(const YAML::Node& root, const std::string& path, int depth, ScenarioConfig* s,
                      bool is_base = false) {
  const Reader r(path);
  r.CheckKeys(root, "", {"base", "scenario", "sweep"});
  if (is_base && root["sweep"].IsDefined()) {
    r.Fail(root["sweep"], "sweep", "only the scenario file that is run may sweep, not a base");
  }
  if (root["base"].IsDefined()) {
    const std::string base = r.String(root["base"], "base");
    const std::string base_path = (fs::path(path).parent_path() / base).lexically_normal().string();
    if (depth > 16) r.Fail(root["base"], "base", "nesting deeper than 16 (a cycle?)");
    if (!std::ifstream(base_path)) r.Fail(root["base"], "base", "cannot open '" + base_path + "'");
    const YAML::Node base_root = LoadYaml(ReadFile(base_path), base_path);
    if (!base_root.IsMap() || !base_root["scenario"].IsDefined()) {
      r.Fail(root["base"], "base", "'" + base_path + "' is not a scenario file");
    }
    LoadScenarioFile(base_root, base_path, depth + 1, s, /*is_base=*/true);
  }
  if (!root["scenario"].IsDefined()) r.Fail(root, "scenario", "missing (a scenario file needs it)");
  ParseScenario(r, root["scenario"], "scenario", s);
  s->source_file = path;
}

// The `key` section in force for a scenario file: its own, or its base chain's nearest one.
YAML::Node EffectiveSection(const YAML::Node& root, const std::string& path, const std::string& key,
                            int depth = 0) {
  if (root["scenario"].IsDefined() && root["scenario"][key].IsDefined()) {
    return root["scenario"][key];
  }
  if (!root["base"].IsDefined() || depth > 16) return YAML::Node(YAML::NodeType::Map);
  const std::string base_path =
      (fs::path(path).parent_path() / root["base"].Scalar()).lexically_normal().string();
  return EffectiveSection(LoadYaml(ReadFile(base_path), base_path), base_path, key, depth + 1);
}

void Finish(const Reader& r, const YAML::Node& at, const std::string& field, ScenarioConfig* s) {
  if (s->name.empty()) r.Fail(at, field + ".name", "missing: every scenario needs a name");
  if (s->points_preset == "random") {
    // The geometry belongs to the scenario: the same points in every trial.
    Rng rng(s->seed, RngStream::kScene);
    s->points.clear();
    for (int i = 0; i < s->points_count; ++i) {
      Eigen::Vector3d p;
      for (int c = 0; c < 3; ++c) p[c] = rng.Uniform(s->random_min[c], s->random_max[c]);
      s->points.push_back(p);
    }
  }
  std::string why;
  for (size_t i = 0; i < s->truth_changes.size(); ++i) {  // Against the final duration_s.
    if (!s->truth_changes[i].Check(s->duration_s, &why)) {
      const std::string mark =
          i < s->truth_change_marks.size() ? s->truth_change_marks[i] : r.file();
      throw config_internal::ConfigError(mark + ": " + field + ".truth.changes[" +
                                         std::to_string(i) + "]: " + why);
    }
  }
  if (!s->Check(&why))
    r.Fail(at, field + "." + why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
}

// One scenario per point of the file's `sweep:`, each the swept scenario plus its override.
void ExpandSweptScenario(const Reader& r, const YAML::Node& root, const std::string& path,
                         const ScenarioConfig& swept, RunConfig* config) {
  if (swept.name.empty())
    r.Fail(root["scenario"], "scenario.name", "missing: every scenario needs a name");
  const std::vector<config_internal::SweepAxis> axes =
      config_internal::ParseSweep(r, root["sweep"]);
  for (size_t i = 0; i < axes.size(); ++i) {
    if (axes[i].methods_only && axes[i].path.size() > 1) {
      config_internal::CheckSweptMethod(
          r, axes[i].field_node, "sweep[" + std::to_string(i) + "].field", axes[i].path[1], swept);
    }
  }
  std::vector<config_internal::SweepPointSpec> points;
  try {
    std::map<std::string, YAML::Node> sections;  // Read once, not once per point.
    points = config_internal::ExpandSweep(axes, swept.name, [&](const std::string& key) {
      auto it = sections.find(key);
      if (it == sections.end()) it = sections.emplace(key, EffectiveSection(root, path, key)).first;
      return it->second;
    });
  } catch (const ConfigError& e) {
    throw ConfigError(path + ": sweep: " + e.what());
  }
  for (const config_internal::SweepPointSpec& spec : points) {
    ScenarioConfig s = swept;
    const std::string field = "sweep point '" + spec.point.params + "'";
    try {
      ParseScenario(r, spec.override_node, field, &s);
      s.name = spec.name;
      s.sweep_point = spec.point;
      Finish(r, spec.override_node, field, &s);
    } catch (const ConfigError& e) {
      // The override is built in memory: its line and column say nothing, the field does.
      std::string what = e.what();
      const size_t at = what.find(field);
      throw ConfigError(path + ": " + (at == std::string::npos ? what : what.substr(at)));
    } catch (const YAML::Exception& e) {
      throw ConfigError(path + ": " + field + ": " + e.what());
    }
    config->scenarios.push_back(std::move(s));
  }
}

void LoadNode(const YAML::Node& root, const std::string& path, int depth, RunConfig* config) {
  const Reader r(path);
  r.ExpectMap(root, "(top level)");
  if (!root["scenarios"].IsDefined()) {
    ScenarioConfig s;
    LoadScenarioFile(root, path, depth, &s);
    if (root["sweep"].IsDefined()) {
      ExpandSweptScenario(r, root, path, s, config);
      return;
    }
    s.sweep_point.sweep = s.name;
    Finish(r, root["scenario"], "scenario", &s);
    config->scenarios.push_back(std::move(s));
    return;
  }
  r.CheckKeys(root, "", {"scenarios"});
  const YAML::Node list = root["scenarios"];
  if (!list.IsSequence()) r.Fail(list, "scenarios", "expected a list of files or scenarios");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string field = "scenarios[" + std::to_string(i) + "]";
    if (list[i].IsScalar()) {
      const std::string child =
          (fs::path(path).parent_path() / list[i].Scalar()).lexically_normal().string();
      LoadFile(child, depth + 1, config);
    } else {
      ScenarioConfig s;
      ParseScenario(r, list[i], field, &s);
      s.source_file = path;
      if (s.sweep_point.sweep.empty()) s.sweep_point.sweep = s.name;
      Finish(r, list[i], field, &s);
      config->scenarios.push_back(std::move(s));
    }
  }
}

void CheckUniqueNames(const RunConfig& config) {
  std::set<std::string> names;
  for (const ScenarioConfig& s : config.scenarios) {
    if (!names.insert(s.name).second) {
      throw ConfigError(s.source_file + ": scenario.name: '" + s.name +
                        "' is used by two scenarios; names key the result rows");
    }
  }
}

}  // namespace

namespace {

// Runs `load` into a fresh RunConfig; *config changes only on success.
bool Guarded(const std::string& path, RunConfig* config, std::string* why,
             const std::function<void(RunConfig*)>& load) {
  return config_internal::CatchConfigErrors(path, why, [&] {
    RunConfig loaded;
    load(&loaded);
    CheckUniqueNames(loaded);
    *config = std::move(loaded);
  });
}

}  // namespace

bool LoadRunConfig(const std::string& path, RunConfig* config, std::string* why) {
  return Guarded(path, config, why, [&](RunConfig* c) { LoadFile(path, 0, c); });
}

bool LoadRunConfigFromString(const std::string& yaml, const std::string& virtual_path,
                             RunConfig* config, std::string* why) {
  return Guarded(virtual_path, config, why,
                 [&](RunConfig* c) { LoadNode(LoadYaml(yaml, virtual_path), virtual_path, 0, c); });
}

}  // namespace calibench
