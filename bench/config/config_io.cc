#include "bench/config/config_io.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bench/config/config_parsers.h"
#include "io/yaml_reader.h"
#include "metrics/tracking.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;
using config_internal::ConfigError;
using config_internal::Reader;

// The form given must be exactly one; its keys and entries are declared (Visit(PointsConfig)).
void ParsePointsSection(const Reader& r, const YAML::Node& node, const std::string& field,
                        PointsConfig* p) {
  r.CheckKeys(node, field, config_internal::DeclaredKeys([](FieldVisitor& v) {
                PointsConfig q;
                Visit(v, q);
              }));
  const bool has_preset = node["preset"].IsDefined();
  const bool has_list = node["list"].IsDefined();
  const bool has_random = node["random"].IsDefined();
  const bool has_boards = node["boards"].IsDefined();
  const bool has_grids = node["aprilgrids"].IsDefined();
  if (has_preset + has_list + has_random + has_boards + has_grids != 1) {
    r.Fail(node, field, "give exactly one of 'preset', 'list', 'random', 'boards' or 'aprilgrids'");
  }
  if (node["count"].IsDefined() && !has_preset) {
    r.Fail(node["count"], field + ".count", "only with a preset");
  }
  const YAML::Node rnd = node["random"];
  if (has_random) {
    const std::string f = Reader::Join(field, "random");
    r.ExpectMap(rnd, f);
    for (const char* key : {"count", "min", "max"}) {
      if (!rnd[key].IsDefined()) r.Fail(rnd, Reader::Join(f, key), "missing");
    }
  }
  *p = PointsConfig();
  config_internal::FieldReader reader(r, node, field, nullptr);
  Visit(reader, *p);
  if (has_grids || has_boards) {  // Counted before the corners are built.
    // Each board and grid passed its Check (a side <= 10000 corners, ids <= a family's 65535
    // codes), so each count fits an int; their sum is taken in int64.
    int64_t corners = 0;
    for (const PlanarBoard& b : p->Boards()) corners += b.NumCorners();
    for (const AprilGrid& g : p->AprilGrids()) corners += 4 * g.NumTags();
    if (corners > kMaxScenarioPoints) {
      r.Fail(node, Reader::Join(field, has_grids ? "aprilgrids" : "boards"),
             std::to_string(corners) + " corners: a scenario has at most " +
                 std::to_string(kMaxScenarioPoints) + " points");
    }
  }
  if (has_grids) {
    p->form = PointsForm::kAprilGrids;
    for (const AprilGrid& g : p->AprilGrids()) {
      const std::vector<Eigen::Vector3d> corners = g.CornersInPointsFrame();
      p->xyz.insert(p->xyz.end(), corners.begin(), corners.end());
    }
  } else if (has_boards) {
    p->form = PointsForm::kBoards;
    p->xyz = RigCorners(p->Boards());
  } else if (has_random) {
    p->form = PointsForm::kRandom;
    const std::string f = Reader::Join(field, "random");
    if (p->count < 1 || p->count > kMaxScenarioPoints) {
      r.Fail(rnd["count"], f + ".count",
             "must lie in [1, " + std::to_string(kMaxScenarioPoints) + "]");
    }
    if (!(p->random_min.array() < p->random_max.array()).all()) {
      r.Fail(rnd, f, "min must be below max in every coordinate");
    }
    return;  // Drawn from the seed once the whole scenario is read (see Finish).
  } else if (has_preset) {
    p->form = PointsForm::kThesis;
    if (p->count < 1 || p->count > 10) {
      r.Fail(node["count"], field + ".count",
             "the thesis preset has 1 to 10 points, got " + std::to_string(p->count));
    }
    p->xyz = ThesisFeaturePoints(p->count);
    return;
  }
  p->count = static_cast<int>(p->xyz.size());
}

}  // namespace

// Applies the scenario mapping `node` onto *s (fields absent from `node` keep their values).
void ParseScenario(const Reader& r, const YAML::Node& node, const std::string& field,
                   ScenarioConfig* s) {
  config_internal::ReadFields(
      r, node, field, [s](FieldVisitor& v) { Visit(v, *s); }, s);
  // A preset motion inherited from a base follows the case.
  if (node["case"].IsDefined() && s->motion_preset) {
    s->motion = ThesisMotionPreset(*s->motion_preset, s->calibration_case);
  }
}

void config_internal::ParsePoints(const Reader& r, const YAML::Node& node, const std::string& field,
                                  PointsConfig* p) {
  ParsePointsSection(r, node, field, p);
}

namespace {

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
  PointsConfig& points = s->points;
  if (points.form == PointsForm::kRandom) {
    // The geometry belongs to the scenario: the same points in every trial.
    Rng rng(s->seed, RngStream::kScene);
    points.xyz.clear();
    for (int i = 0; i < points.count; ++i) {
      Eigen::Vector3d p;
      for (int c = 0; c < 3; ++c) p[c] = rng.Uniform(points.random_min[c], points.random_max[c]);
      points.xyz.push_back(p);
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
  int camera = -1, change = -1;
  std::string rig_field;
  if (!s->CheckRig(&camera, &change, &rig_field, &why)) {  // Where the camera or change is written.
    std::string mark = r.Where(at);
    if (camera >= 0 && camera < static_cast<int>(s->rig.marks.size())) {
      mark = s->rig.marks[camera];
    } else if (change >= 0 && change < static_cast<int>(s->truth_change_marks.size())) {
      mark = s->truth_change_marks[change];
    }
    throw config_internal::ConfigError(mark, field + "." + rig_field, why);
  }
  if (!s->Check(&why))
    r.Fail(at, field + "." + why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
}

// Where the value of `spec` that a failing field (e.g. "noise.pixel_sigma_px") comes from is
// written: the axis sharing the most leading components with it; none sharing one: the file alone
// (the error is not the sweep's).
std::string WhereSweptValueIs(const config_internal::SweepPointSpec& spec,
                              const std::string& failing, const std::string& file) {
  const auto components = [](const std::string& dotted) {
    std::vector<std::string> parts;
    std::stringstream in(dotted);
    for (std::string part; std::getline(in, part, '.');) parts.push_back(part);
    return parts;
  };
  // "points.aprilgrids[1].tag_cols" as the axes write it: "points.aprilgrids.1.tag_cols".
  std::string dotted;
  for (char c : failing) {
    if (c == '[') {
      dotted += '.';
    } else if (c != ']') {
      dotted += c;
    }
  }
  const std::vector<std::string> failing_parts = components(dotted);
  std::string where = file;
  size_t best = 0;
  for (const auto& [axis_field, axis_where] : spec.value_where) {
    const std::vector<std::string> axis_parts = components(axis_field);
    size_t common = 0;
    while (common < axis_parts.size() && common < failing_parts.size() &&
           axis_parts[common] == failing_parts[common]) {
      ++common;
    }
    if (common > best) best = common, where = axis_where;
  }
  return where;
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
      // An error in the override built in memory (its nodes have no place: the file, or 1:1 for
      // nodes cloned into it) is placed at the swept value it names; any other keeps its place
      // (a base's line, a truth change's mark).
      const bool in_override =
          e.field().rfind(field, 0) == 0 && (e.where() == path || e.where() == path + ":1:1");
      if (!in_override) throw;
      std::string failing = e.field().substr(field.size());  // ".noise.pixel_sigma_px"
      if (!failing.empty() && failing[0] == '.') failing.erase(0, 1);
      throw ConfigError(WhereSweptValueIs(spec, failing, path), e.field(), e.reason());
    } catch (const YAML::Exception& e) {
      const std::string where =
          spec.value_where.size() == 1 ? spec.value_where[0].second : std::string(path);
      throw ConfigError(where + ": " + field + ": " + e.what());
    }
    config->scenarios.push_back(std::move(s));
  }
}

// `variants:` of an entry point: each scenario named in a variant's `of` (among those its
// `scenarios:` loaded, from index `first` on) again, as NAME-SUFFIX with the variant's `scenario`
// override applied (sections replace as over a base), its `note` appended to the description.
// The variants follow the scenarios, in the order of the scenarios they vary.
void AddVariants(const Reader& r, const YAML::Node& node, size_t first, RunConfig* config) {
  if (!node.IsSequence() || node.size() == 0) {
    r.Fail(node, "variants", "expected a non-empty list of {suffix, of, scenario, note}");
  }
  std::vector<std::pair<size_t, ScenarioConfig>> variants;  // (index of the varied, variant)
  for (size_t v = 0; v < node.size(); ++v) {
    const std::string field = "variants[" + std::to_string(v) + "]";
    const YAML::Node item = node[v];
    r.CheckKeys(item, field, {"suffix", "note", "of", "scenario"});
    for (const char* key : {"suffix", "of", "scenario"}) {
      if (!item[key].IsDefined()) r.Fail(item, Reader::Join(field, key), "missing");
    }
    const std::string suffix = r.String(item["suffix"], field + ".suffix");
    const std::string note = item["note"] ? r.String(item["note"], field + ".note") : "";
    const YAML::Node of = item["of"];
    if (!of.IsSequence() || of.size() == 0) {
      r.Fail(of, field + ".of", "expected a non-empty list of scenario names");
    }
    for (size_t k = 0; k < of.size(); ++k) {
      const std::string of_field = field + ".of[" + std::to_string(k) + "]";
      const std::string name = r.String(of[k], of_field);
      std::vector<std::string> names;
      size_t index = config->scenarios.size();
      for (size_t i = first; i < config->scenarios.size(); ++i) {
        names.push_back(config->scenarios[i].name);
        if (names.back() == name) index = i;
      }
      if (index == config->scenarios.size()) {
        r.Fail(of[k], of_field, config_internal::NotOneOf(name, names, "scenario"));
      }
      ScenarioConfig s = config->scenarios[index];
      ParseScenario(r, item["scenario"], field + ".scenario", &s);
      s.name += "-" + suffix;
      s.sweep_point.sweep += "-" + suffix;  // A sweep's points vary into one sweep.
      if (!note.empty()) s.description += ", " + note;
      s.source_file = r.file();
      Finish(r, item["scenario"], field + ".scenario", &s);
      variants.emplace_back(index, std::move(s));
    }
  }
  std::stable_sort(variants.begin(), variants.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [index, s] : variants) config->scenarios.push_back(std::move(s));
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
  r.CheckKeys(root, "", {"scenarios", "variants"});
  const YAML::Node list = root["scenarios"];
  if (!list.IsSequence()) r.Fail(list, "scenarios", "expected a list of files or scenarios");
  const size_t first = config->scenarios.size();
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
  if (root["variants"].IsDefined()) AddVariants(r, root["variants"], first, config);
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
