#include "bench/config_io.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/random.h"
#include "core/synthetic.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// Parses one file's nodes, naming the file and the dotted field path in every error.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& field,
                         const std::string& reason) const {
    std::ostringstream msg;
    msg << file_;
    if (node.IsDefined() && node.Mark().line >= 0) {
      msg << ":" << node.Mark().line + 1 << ":" << node.Mark().column + 1;
    }
    msg << ": " << field << ": " << reason;
    throw ConfigError(msg.str());
  }

  void ExpectMap(const YAML::Node& node, const std::string& field) const {
    if (!node.IsMap()) Fail(node, field, "expected a mapping of keys to values");
  }

  // Every key of `node` must be in `allowed`; suggests the closest for a misspelt one.
  void CheckKeys(const YAML::Node& node, const std::string& field,
                 const std::vector<std::string>& allowed) const {
    ExpectMap(node, field);
    for (const auto& kv : node) {
      const std::string key = kv.first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string best;
      size_t best_distance = 3;
      for (const std::string& a : allowed) {
        const size_t d = EditDistance(key, a);
        if (d < best_distance) best_distance = d, best = a;
      }
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      std::string reason = "unknown key";
      if (!best.empty()) reason += " (did you mean '" + best + "'?)";
      reason += "; allowed: ";
      reason += list;
      Fail(kv.first, Join(field, key), reason);
    }
  }

  static std::string Join(const std::string& field, const std::string& key) {
    return field.empty() ? key : field + "." + key;
  }

  // A scalar converted to T; `expected` names the type in the error ("a number").
  template <typename T>
  T Scalar(const YAML::Node& node, const std::string& field, const std::string& expected) const {
    if (!node.IsScalar()) Fail(node, field, "expected " + expected);
    try {
      return node.as<T>();
    } catch (const YAML::Exception&) {
      Fail(node, field, "expected " + expected + ", got '" + node.Scalar() + "'");
    }
  }
  double Double(const YAML::Node& node, const std::string& field) const {
    return Scalar<double>(node, field, "a number");
  }
  long Integer(const YAML::Node& node, const std::string& field) const {
    return Scalar<long>(node, field, "an integer");
  }
  uint64_t Unsigned(const YAML::Node& node, const std::string& field) const {
    // yaml-cpp wraps "-1" to a huge unsigned value: refuse a sign outright.
    if (node.IsScalar() && node.Scalar().find('-') != std::string::npos) {
      Fail(node, field, "expected a non-negative integer, got '" + node.Scalar() + "'");
    }
    return Scalar<uint64_t>(node, field, "a non-negative integer");
  }
  bool Bool(const YAML::Node& node, const std::string& field) const {
    return Scalar<bool>(node, field, "true or false");
  }
  std::string String(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) Fail(node, field, "expected a string");
    return node.Scalar();
  }
  std::string Choice(const YAML::Node& node, const std::string& field,
                     const std::vector<std::string>& choices) const {
    std::string value = String(node, field);
    if (std::find(choices.begin(), choices.end(), value) != choices.end()) return value;
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
    Fail(node, field, "'" + value + "' is not one of: " + list);
  }
  Eigen::Vector3d Vector3(const YAML::Node& node, const std::string& field) const {
    if (!node.IsSequence() || node.size() != 3) Fail(node, field, "expected a list of 3 numbers");
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = Double(node[i], field + "[" + std::to_string(i) + "]");
    return v;
  }
  Eigen::Matrix3d Matrix3(const YAML::Node& node, const std::string& field) const {
    if (!node.IsSequence() || node.size() != 3) {
      Fail(node, field, "expected a 3x3 matrix as a list of 3 rows");
    }
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r) {
      m.row(r) = Vector3(node[r], field + "[" + std::to_string(r) + "]").transpose();
    }
    return m;
  }

  // Calls `apply` when `key` is present in the map `node`.
  template <typename F>
  void If(const YAML::Node& node, const char* key, const std::string& field, F apply) const {
    const YAML::Node child = node[key];
    if (child.IsDefined() && !child.IsNull()) apply(child, Join(field, key));
  }

 private:
  std::string file_;
};

void ParseIntrinsics(const Reader& r, const YAML::Node& node, const std::string& field,
                     CameraIntrinsics* k) {
  r.CheckKeys(node, field,
              {"fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px", "k1", "k2", "p1", "p2", "k3"});
  r.If(node, "fku_px", field, [&](auto n, auto f) { k->fku_px = r.Double(n, f); });
  r.If(node, "fkv_px", field, [&](auto n, auto f) { k->fkv_px = r.Double(n, f); });
  r.If(node, "phi_deg", field, [&](auto n, auto f) { k->phi_deg = r.Double(n, f); });
  r.If(node, "u0_px", field, [&](auto n, auto f) { k->u0_px = r.Double(n, f); });
  r.If(node, "v0_px", field, [&](auto n, auto f) { k->v0_px = r.Double(n, f); });
  r.If(node, "k1", field, [&](auto n, auto f) { k->k1 = r.Double(n, f); });
  r.If(node, "k2", field, [&](auto n, auto f) { k->k2 = r.Double(n, f); });
  r.If(node, "p1", field, [&](auto n, auto f) { k->p1 = r.Double(n, f); });
  r.If(node, "p2", field, [&](auto n, auto f) { k->p2 = r.Double(n, f); });
  r.If(node, "k3", field, [&](auto n, auto f) { k->k3 = r.Double(n, f); });
  std::string why;
  if (!k->Check(&why)) r.Fail(node, field, why);
}

void ParseCamera(const Reader& r, const YAML::Node& node, const std::string& field, CameraSpec* c) {
  r.CheckKeys(node, field, {"intrinsics", "R_C", "x_C", "allow_improper_rotation"});
  r.If(node, "allow_improper_rotation", field,
       [&](auto n, auto f) { c->allow_improper_rotation = r.Bool(n, f); });
  r.If(node, "intrinsics", field,
       [&](auto n, auto f) { ParseIntrinsics(r, n, f, &c->intrinsics); });
  r.If(node, "x_C", field, [&](auto n, auto f) { c->x_c = r.Vector3(n, f); });
  r.If(node, "R_C", field, [&](auto n, auto f) { c->r_c = r.Matrix3(n, f); });
  // Checked on every file that sets or opts in, so an override can allow a base's matrix.
  if (node["R_C"].IsDefined() || node["allow_improper_rotation"].IsDefined()) {
    std::string why;
    const YAML::Node at = node["R_C"].IsDefined() ? node["R_C"] : node;
    if (!CheckRotation(c->r_c, 1e-9, c->allow_improper_rotation, &why)) {
      r.Fail(at, Reader::Join(field, "R_C"), why);
    }
  }
}

void ParsePoints(const Reader& r, const YAML::Node& node, const std::string& field,
                 ScenarioConfig* s) {
  r.CheckKeys(node, field, {"preset", "count", "list", "random"});
  const bool has_preset = node["preset"].IsDefined();
  const bool has_list = node["list"].IsDefined();
  const bool has_random = node["random"].IsDefined();
  if (has_preset + has_list + has_random != 1) {
    r.Fail(node, field, "give exactly one of 'preset', 'list' or 'random'");
  }
  s->points.clear();
  s->points_preset.clear();
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
               "frequency_rad_s", "frame"});
  s->motion = TwistProfile();
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
  r.If(node, "v_const", field, [&](auto n, auto f) { m.v_const = r.Vector3(n, f); });
  r.If(node, "v_cos", field, [&](auto n, auto f) { m.v_cos = r.Vector3(n, f); });
  r.If(node, "v_sin", field, [&](auto n, auto f) { m.v_sin = r.Vector3(n, f); });
  r.If(node, "w_const", field, [&](auto n, auto f) { m.w_const = r.Vector3(n, f); });
  r.If(node, "w_cos", field, [&](auto n, auto f) { m.w_cos = r.Vector3(n, f); });
  r.If(node, "w_sin", field, [&](auto n, auto f) { m.w_sin = r.Vector3(n, f); });
  r.If(node, "frequency_rad_s", field, [&](auto n, auto f) { m.frequency_rad_s = r.Double(n, f); });
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

void ParseAdaptive(const Reader& r, const YAML::Node& node, const std::string& field,
                   AdaptiveMethodConfig* a) {
  r.CheckKeys(node, field,
              {"enabled", "alpha", "gamma0", "rtol", "max_step_s", "initial_step_s", "max_steps",
               "convergence_tol", "initial"});
  AdaptiveOptions& o = a->options;
  r.If(node, "enabled", field, [&](auto n, auto f) { a->enabled = r.Bool(n, f); });
  r.If(node, "alpha", field, [&](auto n, auto f) { o.alpha = r.Double(n, f); });
  r.If(node, "gamma0", field, [&](auto n, auto f) { o.gamma0 = r.Double(n, f); });
  r.If(node, "rtol", field, [&](auto n, auto f) { o.rtol = r.Double(n, f); });
  r.If(node, "max_step_s", field, [&](auto n, auto f) { o.max_step_s = r.Double(n, f); });
  r.If(node, "initial_step_s", field, [&](auto n, auto f) { o.initial_step_s = r.Double(n, f); });
  r.If(node, "max_steps", field, [&](auto n, auto f) { o.max_steps = r.Integer(n, f); });
  r.If(node, "convergence_tol", field,
       [&](auto n, auto f) { a->convergence_tol = r.Double(n, f); });
  r.If(node, "initial", field, [&](auto n, auto f) { ParseCamera(r, n, f, &a->initial); });
  std::string why;
  if (!o.Check(&why)) r.Fail(node, field, why);
  if (!(a->convergence_tol > 0))
    r.Fail(node, Reader::Join(field, "convergence_tol"), "must be > 0");
}

void ParseDlt(const Reader& r, const YAML::Node& node, const std::string& field,
              DltMethodConfig* d) {
  r.CheckKeys(node, field, {"enabled", "min_planarity_ratio"});
  r.If(node, "enabled", field, [&](auto n, auto f) { d->enabled = r.Bool(n, f); });
  r.If(node, "min_planarity_ratio", field,
       [&](auto n, auto f) { d->options.min_planarity_ratio = r.Double(n, f); });
  std::string why;
  if (!d->options.Check(&why)) r.Fail(node, field, why);
}

void ParseCeres(const Reader& r, const YAML::Node& node, const std::string& field,
                CeresMethodConfig* c) {
  r.CheckKeys(
      node, field,
      {"enabled", "init", "model", "estimate_skew", "loss", "loss_scale_px", "max_iterations"});
  RefineOptions& o = c->options;
  r.If(node, "enabled", field, [&](auto n, auto f) { c->enabled = r.Bool(n, f); });
  r.If(node, "init", field, [&](auto n, auto f) { c->init = r.Choice(n, f, {"dlt"}); });
  r.If(node, "model", field, [&](auto n, auto f) {
    ParseLensModel(r.Choice(n, f, {"pinhole", "pinhole-k2", "pinhole-radtan4", "pinhole-radtan5"}),
                   &o.model);
  });
  r.If(node, "estimate_skew", field, [&](auto n, auto f) { o.estimate_skew = r.Bool(n, f); });
  r.If(node, "loss", field, [&](auto n, auto f) {
    o.loss = r.Choice(n, f, {"none", "huber", "cauchy"});
  });
  r.If(node, "loss_scale_px", field, [&](auto n, auto f) { o.loss_scale_px = r.Double(n, f); });
  r.If(node, "max_iterations", field,
       [&](auto n, auto f) { o.max_iterations = static_cast<int>(r.Integer(n, f)); });
  std::string why;
  if (!o.Check(&why)) r.Fail(node, field, why);
}

void ParseReference(const Reader& r, const YAML::Node& node, const std::string& field,
                    Reference* ref) {
  r.CheckKeys(
      node, field,
      {"source", "fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px", "x_C", "theta_err_below"});
  *ref = Reference();
  r.If(node, "source", field, [&](auto n, auto f) { ref->source = r.String(n, f); });
  r.If(node, "fku_px", field, [&](auto n, auto f) { ref->fku_px = r.Double(n, f); });
  r.If(node, "fkv_px", field, [&](auto n, auto f) { ref->fkv_px = r.Double(n, f); });
  r.If(node, "phi_deg", field, [&](auto n, auto f) { ref->phi_deg = r.Double(n, f); });
  r.If(node, "u0_px", field, [&](auto n, auto f) { ref->u0_px = r.Double(n, f); });
  r.If(node, "v0_px", field, [&](auto n, auto f) { ref->v0_px = r.Double(n, f); });
  r.If(node, "x_C", field, [&](auto n, auto f) { ref->x_c = r.Vector3(n, f); });
  r.If(node, "theta_err_below", field,
       [&](auto n, auto f) { ref->theta_err_below = r.Double(n, f); });
}

// Applies the scenario mapping `node` onto *s (fields absent from `node` keep their values).
void ParseScenario(const Reader& r, const YAML::Node& node, const std::string& field,
                   ScenarioConfig* s) {
  r.CheckKeys(node, field,
              {"name", "description", "case", "duration_s", "seed", "trials", "truth", "points",
               "motion", "measurements", "noise", "methods", "reference"});
  r.If(node, "name", field, [&](auto n, auto f) { s->name = r.String(n, f); });
  r.If(node, "description", field, [&](auto n, auto f) { s->description = r.String(n, f); });
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
    if (!(s->duration_s > 0)) r.Fail(n, f, "must be > 0");
  });
  r.If(node, "seed", field, [&](auto n, auto f) { s->seed = r.Unsigned(n, f); });
  r.If(node, "trials", field, [&](auto n, auto f) {
    const long trials = r.Integer(n, f);
    if (trials < 1) r.Fail(n, f, "must be >= 1, got " + std::to_string(trials));
    s->trials = static_cast<int>(trials);
  });
  r.If(node, "truth", field, [&](auto n, auto f) { ParseCamera(r, n, f, &s->truth); });
  r.If(node, "points", field, [&](auto n, auto f) { ParsePoints(r, n, f, s); });
  r.If(node, "motion", field, [&](auto n, auto f) { ParseMotion(r, n, f, s); });
  r.If(node, "measurements", field, [&](auto n, auto f) {
    r.CheckKeys(n, f, {"detections", "sample_rate_hz", "eval_rate_hz"});
    r.If(n, "detections", f, [&](auto m, auto g) { s->detections = r.Choice(m, g, {"oracle"}); });
    r.If(n, "sample_rate_hz", f,
         [&](auto m, auto g) { s->measurements.sample_rate_hz = r.Double(m, g); });
    r.If(n, "eval_rate_hz", f,
         [&](auto m, auto g) { s->measurements.eval_rate_hz = r.Double(m, g); });
    std::string why;
    OracleOptions check = s->measurements;
    check.noise = NoiseOptions();
    if (!check.Check(&why)) r.Fail(n, f, why);
  });
  r.If(node, "noise", field, [&](auto n, auto f) {
    r.CheckKeys(n, f, {"point_sigma_m", "pixel_sigma_px", "hold_s"});
    NoiseOptions& noise = s->measurements.noise;
    r.If(n, "point_sigma_m", f, [&](auto m, auto g) { noise.point_sigma_m = r.Double(m, g); });
    r.If(n, "pixel_sigma_px", f, [&](auto m, auto g) { noise.pixel_sigma_px = r.Double(m, g); });
    r.If(n, "hold_s", f, [&](auto m, auto g) { noise.hold_s = r.Double(m, g); });
    std::string why;
    if (!noise.Check(&why)) r.Fail(n, f, why);
  });
  r.If(node, "methods", field, [&](auto n, auto f) {
    r.CheckKeys(n, f, {"adaptive", "dlt", "ceres"});
    r.If(n, "adaptive", f, [&](auto m, auto g) { ParseAdaptive(r, m, g, &s->adaptive); });
    r.If(n, "dlt", f, [&](auto m, auto g) { ParseDlt(r, m, g, &s->dlt); });
    r.If(n, "ceres", f, [&](auto m, auto g) { ParseCeres(r, m, g, &s->ceres); });
  });
  r.If(node, "reference", field, [&](auto n, auto f) { ParseReference(r, n, f, &s->reference); });
}

YAML::Node LoadYaml(const std::string& text, const std::string& path) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    std::ostringstream msg;
    msg << path << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
        << ": (yaml): malformed YAML: " << e.msg;
    throw ConfigError(msg.str());
  }
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": (file): cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void LoadNode(const YAML::Node& root, const std::string& path, int depth, RunConfig* config);

void LoadFile(const std::string& path, int depth, RunConfig* config) {
  if (depth > 16) throw ConfigError(path + ": (include): nesting deeper than 16 (a cycle?)");
  LoadNode(LoadYaml(ReadFile(path), path), path, depth, config);
}

// Loads the scenario of a scenario file (following `base:`) into *s.
void LoadScenarioFile(const YAML::Node& root, const std::string& path, int depth,
                      ScenarioConfig* s) {
  const Reader r(path);
  r.CheckKeys(root, "", {"base", "scenario"});
  if (root["base"].IsDefined()) {
    const std::string base = r.String(root["base"], "base");
    const std::string base_path = (fs::path(path).parent_path() / base).lexically_normal().string();
    if (depth > 16) r.Fail(root["base"], "base", "nesting deeper than 16 (a cycle?)");
    if (!std::ifstream(base_path)) r.Fail(root["base"], "base", "cannot open '" + base_path + "'");
    const YAML::Node base_root = LoadYaml(ReadFile(base_path), base_path);
    if (!base_root.IsMap() || !base_root["scenario"].IsDefined()) {
      r.Fail(root["base"], "base", "'" + base_path + "' is not a scenario file");
    }
    LoadScenarioFile(base_root, base_path, depth + 1, s);
  }
  if (!root["scenario"].IsDefined()) r.Fail(root, "scenario", "missing (a scenario file needs it)");
  ParseScenario(r, root["scenario"], "scenario", s);
  s->source_file = path;
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
  if (!s->Check(&why))
    r.Fail(at, field + "." + why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
}

void LoadNode(const YAML::Node& root, const std::string& path, int depth, RunConfig* config) {
  const Reader r(path);
  r.ExpectMap(root, "(top level)");
  if (!root["scenarios"].IsDefined()) {
    ScenarioConfig s;
    LoadScenarioFile(root, path, depth, &s);
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

// --- Writing -------------------------------------------------------------------------------

void EmitVector(YAML::Emitter& out, const Eigen::Vector3d& v) {
  out << YAML::Flow << YAML::BeginSeq << v[0] << v[1] << v[2] << YAML::EndSeq;
}

void EmitCamera(YAML::Emitter& out, const CameraSpec& c) {
  const CameraIntrinsics& k = c.intrinsics;
  out << YAML::BeginMap << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "fku_px" << YAML::Value << k.fku_px << YAML::Key << "fkv_px" << YAML::Value
      << k.fkv_px << YAML::Key << "phi_deg" << YAML::Value << k.phi_deg << YAML::Key << "u0_px"
      << YAML::Value << k.u0_px << YAML::Key << "v0_px" << YAML::Value << k.v0_px << YAML::Key
      << "k1" << YAML::Value << k.k1 << YAML::Key << "k2" << YAML::Value << k.k2 << YAML::Key
      << "p1" << YAML::Value << k.p1 << YAML::Key << "p2" << YAML::Value << k.p2 << YAML::Key
      << "k3" << YAML::Value << k.k3 << YAML::EndMap;
  out << YAML::Key << "R_C" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int r = 0; r < 3; ++r) EmitVector(out, c.r_c.row(r).transpose());
  out << YAML::EndSeq << YAML::Key << "x_C" << YAML::Value;
  EmitVector(out, c.x_c);
  out << YAML::Key << "allow_improper_rotation" << YAML::Value << c.allow_improper_rotation
      << YAML::EndMap;
}

void EmitScenario(YAML::Emitter& out, const ScenarioConfig& s) {
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << s.name;
  out << YAML::Key << "description" << YAML::Value << s.description;
  out << YAML::Key << "case" << YAML::Value << ToString(s.calibration_case);
  out << YAML::Key << "duration_s" << YAML::Value << s.duration_s;
  out << YAML::Key << "seed" << YAML::Value << s.seed;
  out << YAML::Key << "trials" << YAML::Value << s.trials;
  out << YAML::Key << "truth" << YAML::Value;
  EmitCamera(out, s.truth);
  out << YAML::Key << "points" << YAML::Value << YAML::BeginMap << YAML::Key << "list"
      << YAML::Value << YAML::BeginSeq;
  for (const Eigen::Vector3d& p : s.points) EmitVector(out, p);
  out << YAML::EndSeq << YAML::EndMap;
  const TwistProfile& m = s.motion;
  out << YAML::Key << "motion" << YAML::Value << YAML::BeginMap;
  const std::pair<const char*, const Eigen::Vector3d*> parts[] = {
      {"v_const", &m.v_const}, {"v_cos", &m.v_cos}, {"v_sin", &m.v_sin},
      {"w_const", &m.w_const}, {"w_cos", &m.w_cos}, {"w_sin", &m.w_sin}};
  for (const auto& [key, v] : parts) {
    out << YAML::Key << key << YAML::Value;
    EmitVector(out, *v);
  }
  out << YAML::Key << "frequency_rad_s" << YAML::Value << m.frequency_rad_s;
  out << YAML::Key << "frame" << YAML::Value
      << (m.frame == TwistProfile::Frame::kWorld ? "world" : "body") << YAML::EndMap;
  out << YAML::Key << "measurements" << YAML::Value << YAML::BeginMap << YAML::Key << "detections"
      << YAML::Value << s.detections << YAML::Key << "sample_rate_hz" << YAML::Value
      << s.measurements.sample_rate_hz << YAML::Key << "eval_rate_hz" << YAML::Value
      << s.measurements.eval_rate_hz << YAML::EndMap;
  const NoiseOptions& n = s.measurements.noise;
  out << YAML::Key << "noise" << YAML::Value << YAML::BeginMap << YAML::Key << "point_sigma_m"
      << YAML::Value << n.point_sigma_m << YAML::Key << "pixel_sigma_px" << YAML::Value
      << n.pixel_sigma_px << YAML::Key << "hold_s" << YAML::Value << n.hold_s << YAML::EndMap;
  const AdaptiveMethodConfig& a = s.adaptive;
  out << YAML::Key << "methods" << YAML::Value << YAML::BeginMap << YAML::Key << "adaptive"
      << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "enabled" << YAML::Value << a.enabled;
  out << YAML::Key << "alpha" << YAML::Value << a.options.alpha;
  out << YAML::Key << "gamma0" << YAML::Value << a.options.gamma0;
  out << YAML::Key << "rtol" << YAML::Value << a.options.rtol;
  out << YAML::Key << "max_step_s" << YAML::Value << a.options.max_step_s;
  out << YAML::Key << "initial_step_s" << YAML::Value << a.options.initial_step_s;
  out << YAML::Key << "max_steps" << YAML::Value << a.options.max_steps;
  out << YAML::Key << "convergence_tol" << YAML::Value << a.convergence_tol;
  out << YAML::Key << "initial" << YAML::Value;
  EmitCamera(out, a.initial);
  out << YAML::EndMap;
  out << YAML::Key << "dlt" << YAML::Value << YAML::BeginMap << YAML::Key << "enabled"
      << YAML::Value << s.dlt.enabled << YAML::Key << "min_planarity_ratio" << YAML::Value
      << s.dlt.options.min_planarity_ratio << YAML::EndMap;
  const RefineOptions& c = s.ceres.options;
  out << YAML::Key << "ceres" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "enabled" << YAML::Value << s.ceres.enabled;
  out << YAML::Key << "init" << YAML::Value << s.ceres.init;
  out << YAML::Key << "model" << YAML::Value << ToString(c.model);
  out << YAML::Key << "estimate_skew" << YAML::Value << c.estimate_skew;
  out << YAML::Key << "loss" << YAML::Value << c.loss;
  out << YAML::Key << "loss_scale_px" << YAML::Value << c.loss_scale_px;
  out << YAML::Key << "max_iterations" << YAML::Value << c.max_iterations;
  out << YAML::EndMap << YAML::EndMap;
  const Reference& ref = s.reference;
  if (ref.Any() || !ref.source.empty()) {
    out << YAML::Key << "reference" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "source" << YAML::Value << ref.source;
    const std::pair<const char*, double> values[] = {
        {"fku_px", ref.fku_px}, {"fkv_px", ref.fkv_px}, {"phi_deg", ref.phi_deg},
        {"u0_px", ref.u0_px},   {"v0_px", ref.v0_px},   {"theta_err_below", ref.theta_err_below}};
    for (const auto& [key, v] : values) {
      if (std::isfinite(v)) out << YAML::Key << key << YAML::Value << v;
    }
    if (ref.x_c.allFinite()) {
      out << YAML::Key << "x_C" << YAML::Value;
      EmitVector(out, ref.x_c);
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

}  // namespace

namespace {

// Runs `load` into a fresh RunConfig; *config changes only on success.
bool Guarded(const std::string& path, RunConfig* config, std::string* why,
             const std::function<void(RunConfig*)>& load) {
  try {
    RunConfig loaded;
    load(&loaded);
    CheckUniqueNames(loaded);
    *config = std::move(loaded);
    return true;
  } catch (const ConfigError& e) {
    if (why) *why = e.what();
  } catch (const YAML::Exception& e) {
    if (why) *why = path + ": (yaml): " + e.what();
  }
  return false;
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

std::string ResolvedYaml(const RunConfig& config) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::Comment("calibench resolved configuration: every default filled in");
  out << YAML::BeginMap << YAML::Key << "scenarios" << YAML::Value << YAML::BeginSeq;
  for (const ScenarioConfig& s : config.scenarios) EmitScenario(out, s);
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace calibench
