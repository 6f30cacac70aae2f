// Sweep axes of a scenario file: parsing `sweep:` and expanding it into per-point override
// mappings (config I/O; see config_io.h for the syntax and config_parsers.h for the contract).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>

#include "bench/config/config_parsers.h"
#include "util/format.h"

namespace calibench {
namespace config_internal {
namespace {

// The scenario keys an axis may start with ("name" keys the rows; sweep_point is ours).
// The top-level scenario fields a sweep axis may start with (declared: scenario_fields.cc).
const std::set<std::string>& SweepableFields() {
  static const std::set<std::string> keys = [] {
    const std::vector<std::string> list = SweepableKeys();
    return std::set<std::string>(list.begin(), list.end());
  }();
  return keys;
}

std::vector<std::string> SplitPath(const std::string& field) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = field.find('.', start);
    parts.push_back(field.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

// Range values as text: 12 digits, so that from + i * step prints as the user would write it.
std::string RangeValueText(double v) { return FormatNumber(v, 12); }

// The values of a `range: {from, to, step | log_step}` axis, as YAML scalars.
std::vector<YAML::Node> RangeValues(const Reader& r, const YAML::Node& range,
                                    const std::string& field) {
  r.CheckKeys(range, field, {"from", "to", "step", "log_step"});
  for (const char* key : {"from", "to"}) {
    if (!range[key].IsDefined()) r.Fail(range, Reader::Join(field, key), "missing");
  }
  const bool linear = range["step"].IsDefined();
  if (linear == range["log_step"].IsDefined()) {
    r.Fail(range, field, "give exactly one of 'step' (added) or 'log_step' (multiplied)");
  }
  const double from = r.Double(range["from"], field + ".from");
  const double to = r.Double(range["to"], field + ".to");
  if (!std::isfinite(from) || !std::isfinite(to) || to < from) {
    r.Fail(range, field, "needs finite from <= to");
  }
  constexpr int kMaxValues = 10000;
  std::vector<YAML::Node> values;
  if (linear) {
    const double step = r.Double(range["step"], field + ".step");
    if (!(step > 0)) r.Fail(range["step"], field + ".step", "must be > 0");
    const double count = std::floor((to - from) / step + 1e-9) + 1;
    if (count > kMaxValues) r.Fail(range, field, "more than 10000 values");
    for (int i = 0; i < static_cast<int>(count); ++i) {
      values.emplace_back(RangeValueText(from + i * step));
    }
  } else {
    const double factor = r.Double(range["log_step"], field + ".log_step");
    if (!(factor > 1)) r.Fail(range["log_step"], field + ".log_step", "must be > 1");
    if (!(from > 0)) r.Fail(range["from"], field + ".from", "must be > 0 with log_step");
    // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter): the values are this product.
    for (double v = from; v <= to * (1 + 1e-9); v *= factor) {
      if (static_cast<int>(values.size()) >= kMaxValues)
        r.Fail(range, field, "more than 10000 values");
      values.emplace_back(RangeValueText(v));
    }
  }
  return values;
}

std::string ValueText(const YAML::Node& value) {
  if (value.IsScalar()) return value.Scalar();
  YAML::Emitter out;
  out << YAML::Flow << value;
  return out.c_str();
}

bool IsIndex(const std::string& key) {
  return !key.empty() && key.find_first_not_of("0123456789") == std::string::npos;
}

// Sets `path` inside `node`, creating mappings on the way; numeric components index sequences.
void SetPath(const YAML::Node& node, const std::vector<std::string>& path, size_t from,
             const YAML::Node& value) {
  YAML::Node current = node;
  for (size_t i = from; i + 1 < path.size(); ++i) {
    const std::string& key = path[i];
    if (current.IsSequence() && IsIndex(key)) {
      const size_t k = std::stoul(key);
      if (k >= current.size()) {
        throw ConfigError("index " + key + " is past the end of a list of " +
                          std::to_string(current.size()));
      }
      current.reset(current[k]);
    } else {
      if (!current[key].IsDefined() || !current[key].IsMap()) {
        if (current[key].IsDefined() && !current[key].IsNull() && !current[key].IsSequence()) {
          throw ConfigError("'" + key + "' is not a mapping");
        }
        if (!current[key].IsDefined() || current[key].IsNull())
          current[key] = YAML::Node(YAML::NodeType::Map);
      }
      current.reset(current[key]);
    }
  }
  const std::string& last = path.back();
  if (current.IsSequence() && IsIndex(last)) {
    const size_t k = std::stoul(last);
    if (k >= current.size()) throw ConfigError("index " + last + " is past the end of a list");
    current[k] = YAML::Clone(value);
  } else {
    current[last] = YAML::Clone(value);
  }
}

}  // namespace

std::vector<SweepAxis> ParseSweep(const Reader& r, const YAML::Node& node) {
  if (!node.IsSequence() || node.size() == 0) {
    r.Fail(node, "sweep", "expected a non-empty list of axes {field, values | range}");
  }
  std::vector<SweepAxis> axes;
  std::set<std::string> seen;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string f = "sweep[" + std::to_string(i) + "]";
    const YAML::Node item = node[i];
    r.CheckKeys(item, f, {"field", "values", "range"});
    if (!item["field"].IsDefined()) r.Fail(item, f + ".field", "missing");
    SweepAxis axis;
    axis.field = r.String(item["field"], f + ".field");
    axis.field_node = item["field"];
    axis.path = SplitPath(axis.field);
    for (const std::string& part : axis.path) {
      if (part.empty())
        r.Fail(item["field"], f + ".field", "empty component in '" + axis.field + "'");
    }
    if (!SweepableFields().count(axis.path[0])) {
      r.Fail(item["field"], f + ".field",
             "'" + axis.path[0] + "' is not a scenario field that can be swept");
    }
    if (!seen.insert(axis.field).second) r.Fail(item["field"], f + ".field", "swept twice");
    if (item["values"].IsDefined() == item["range"].IsDefined()) {
      r.Fail(item, f, "give exactly one of 'values' (a list) or 'range'");
    }
    if (item["values"].IsDefined()) {
      const YAML::Node values = item["values"];
      if (!values.IsSequence() || values.size() == 0) {
        r.Fail(values, f + ".values", "expected a non-empty list");
      }
      for (size_t k = 0; k < values.size(); ++k) {
        axis.values.push_back(values[k]);
        axis.where.push_back(r.Where(values[k]));
      }
    } else {
      axis.values = RangeValues(r, item["range"], f + ".range");
      axis.where.assign(axis.values.size(), r.Where(item["range"]));
    }
    axis.methods_only = axis.path[0] == "methods";
    axes.push_back(std::move(axis));
  }
  return axes;
}

std::vector<SweepPointSpec> ExpandSweep(
    std::vector<SweepAxis> axes, const std::string& sweep_name,
    const std::function<YAML::Node(const std::string& key)>& wholesale_section) {
  // Measurement axes outermost, method axes fastest: a measurement group is consecutive.
  std::stable_partition(axes.begin(), axes.end(),
                        [](const SweepAxis& a) { return !a.methods_only; });
  size_t total = 1, measurement_total = 1;
  for (const SweepAxis& a : axes) {
    total *= a.values.size();
    if (!a.methods_only) measurement_total *= a.values.size();
  }
  if (total > 100000)
    throw ConfigError("the product of the axes has " + std::to_string(total) +
                      " points (at most 100000)");
  const size_t per_measurement = total / measurement_total;
  std::vector<SweepPointSpec> points;
  std::vector<size_t> digit(axes.size(), 0);
  for (size_t index = 0; index < total; ++index) {
    size_t rest = index;
    for (size_t a = axes.size(); a-- > 0;) {
      digit[a] = rest % axes[a].values.size();
      rest /= axes[a].values.size();
    }
    SweepPointSpec spec;
    spec.override_node = YAML::Node(YAML::NodeType::Map);
    spec.point.sweep = sweep_name;
    spec.point.index = static_cast<int>(index);
    spec.point.measurement_index = static_cast<int>(index / per_measurement);
    std::string names;
    for (size_t a = 0; a < axes.size(); ++a) {
      const SweepAxis& axis = axes[a];
      const YAML::Node& value = axis.values[digit[a]];
      const std::string& key = axis.path[0];
      if ((key == "points" || key == "motion" || key == "reference") &&
          !spec.override_node[key].IsDefined()) {
        // These sections replace a base's as a whole: start from the one in force.
        spec.override_node[key] = YAML::Clone(wholesale_section(key));
      }
      if (axis.path.size() > 1 && !spec.override_node[key].IsDefined()) {
        spec.override_node[key] = YAML::Node(YAML::NodeType::Map);
      }
      if (axis.path.size() == 1) {
        spec.override_node[key] = YAML::Clone(value);
      } else {
        try {
          SetPath(spec.override_node[key], axis.path, 1, value);
        } catch (const ConfigError& e) {
          throw ConfigError("sweep field '" + axis.field + "': " + e.what());
        }
      }
      spec.value_where.emplace_back(axis.field, axis.where[digit[a]]);
      const std::string pair = axis.field + "=" + ValueText(value);
      names += (names.empty() ? "" : ",") + pair;
      spec.point.params += (spec.point.params.empty() ? "" : ";") + pair;
    }
    spec.name = sweep_name + "[" + names + "]";
    points.push_back(std::move(spec));
  }
  return points;
}

}  // namespace config_internal
}  // namespace calibench
