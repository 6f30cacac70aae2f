#include "bench/run/schema.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "bench/run/run_row.h"
#include "bench/run/summary.h"
#include "methods/registry.h"
#include "metrics/metric_table.h"
#include "util/format.h"

namespace calibench {
namespace {

// A JSON string: quotes, backslashes and control characters escaped; UTF-8 passes through.
std::string Quote(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string Bool(bool b) { return b ? "true" : "false"; }

// "[a, b, ...]" of already formatted JSON values, one per line at `indent`.
std::string List(const std::vector<std::string>& items, const std::string& indent) {
  if (items.empty()) return "[]";
  std::string out = "[\n";
  for (size_t i = 0; i < items.size(); ++i) {
    out += indent + "  " + items[i] + (i + 1 < items.size() ? ",\n" : "\n");
  }
  return out + indent + "]";
}

const char* kNamingRule[] = {
    "Lower-case words joined by '_'; a column holding a dimensional number ends in its unit "
    "(_px, _deg, _m, _s, _ms, _us); a dimensionless one (count, flag, ratio, index, ||theta~||, "
    "NEES) has no unit.",
    "A quantity Q is named with its unit (fku_px, pitch_deg); its columns: Q the estimate, err_Q "
    "estimate minus truth, std_Q the reported standard deviation, crlb_Q the Cramer-Rao standard "
    "deviation (runs.csv); est_Q and true_Q over time (tracks.csv), err_Q (track_errors.csv).",
    "A figure that is not a parameter is one column, unit last: rot_err_deg, xc_err_m, "
    "rms_reproj_px, converge_time_s, corner_rms_px.",
    "A long table names the quantity of a row in its metric (summary.csv) or quantity "
    "(events.csv, track_bands.csv) column, unit included; the row's value columns are in that "
    "unit.",
};

// Rig runs' amendment (rig.csv's units).
const char* kRigNamingRule =
    "Rig runs: rig.csv also has _mm (millimetres: err_baseline_mm) and _pct (percent of the true "
    "value: depth_err_10m_pct); every per-row file, summary.csv and track_bands.csv end in a "
    "camera column.";

std::string QuantityJson(const MetricSpec& m) {
  std::vector<std::string> columns;
  const std::pair<MetricColumn, const char*> kinds[] = {
      {kValueColumn, "value"}, {kErrorColumn, "error"}, {kStdColumn, "std"}, {kCrlbColumn, "crlb"}};
  for (const auto& [kind, key] : kinds) {
    if (m.columns & kind) columns.push_back(Quote(key) + ": " + Quote(ColumnName(m, kind)));
  }
  std::string cols = "{";
  for (size_t i = 0; i < columns.size(); ++i) cols += (i ? ", " : "") + columns[i];
  cols += "}";
  const char* summary = m.summary == Summary::kNone         ? "null"
                        : m.summary == Summary::kStatistics ? "\"statistics\""
                                                            : "\"with_rmse\"";
  return "{\"name\": " + Quote(m.name) + ", \"unit\": " + Quote(m.unit) +
         ", \"label\": " + Quote(m.label) + ", \"doc\": " + Quote(m.doc) +
         ", \"columns\": " + cols + ", \"integer\": " + Bool(m.integer) +
         ", \"tracked\": " + Bool(m.track >= 0) + ", \"summary\": " + summary +
         ", \"summary_metric\": " +
         (m.summary == Summary::kNone ? std::string("null") : Quote(SummaryColumn(m))) +
         ", \"ranked\": " + Bool(m.ranked) +
         ", \"target\": " + (m.target > 0 ? FormatNumber(m.target) : std::string("null")) +
         ", \"headline\": " + Bool(m.headline) +
         ", \"projection\": " + (m.projection ? Quote(m.projection) : std::string("null")) + "}";
}

std::string FileJson(const std::vector<ColumnInfo>& columns, const std::string& indent) {
  std::vector<std::string> items;
  items.reserve(columns.size());
  for (const ColumnInfo& c : columns) {
    items.push_back("{\"name\": " + Quote(c.name) + ", \"unit\": " + Quote(c.unit) +
                    ", \"doc\": " + Quote(c.doc) + "}");
  }
  return List(items, indent);
}

// The fields of a sweep point's params "field=value;field=value".
std::vector<std::string> AxisFields(const std::string& params) {
  std::vector<std::string> fields;
  size_t start = 0;
  while (start < params.size()) {
    size_t end = params.find(';', start);
    if (end == std::string::npos) end = params.size();
    const std::string part = params.substr(start, end - start);
    fields.push_back(part.substr(0, part.find('=')));
    start = end + 1;
  }
  return fields;
}

std::string SweepsJson(const RunConfig& config, const std::string& indent) {
  struct Sweep {
    std::string role, detections;
    std::vector<std::string> axes;
    int points = 0, trials = 0;
    bool tracks = false;
  };
  std::vector<std::string> order;
  std::map<std::string, Sweep> sweeps;
  for (const ScenarioConfig& s : config.scenarios) {
    const std::string& name = s.sweep_point.sweep.empty() ? s.name : s.sweep_point.sweep;
    auto [it, fresh] = sweeps.emplace(name, Sweep());
    Sweep& w = it->second;
    if (fresh) {
      order.push_back(name);
      if (s.report.role != ReportRole::kNone) w.role = ReportRoleNames().Name(s.report.role);
      w.detections = ToString(s.detections);
      w.axes = AxisFields(s.sweep_point.params);
    }
    ++w.points;
    w.trials = std::max(w.trials, s.trials);
    w.tracks = w.tracks || s.Tracks();
  }
  std::vector<std::string> items;
  for (const std::string& name : order) {
    const Sweep& w = sweeps.at(name);
    std::string axes = "[";
    for (size_t i = 0; i < w.axes.size(); ++i) axes += (i ? ", " : "") + Quote(w.axes[i]);
    axes += "]";
    items.push_back("{\"sweep\": " + Quote(name) + ", \"role\": " + Quote(w.role) +
                    ", \"detections\": " + Quote(w.detections) + ", \"axes\": " + axes +
                    ", \"points\": " + std::to_string(w.points) + ", \"trials\": " +
                    std::to_string(w.trials) + ", \"tracks\": " + Bool(w.tracks) + "}");
  }
  return List(items, indent);
}

// Per registered type, in registry order: its family, the outputs it declares and its windup law.
std::string MethodsJson(const std::string& indent) {
  auto names = [](const std::vector<std::string>& quoted) {
    std::string out = "[";
    for (size_t i = 0; i < quoted.size(); ++i) out += (i ? ", " : "") + quoted[i];
    return out + "]";
  };
  std::vector<std::string> items;
  for (const MethodType& t : MethodTypes()) {
    const std::unique_ptr<Method> method = t.create();
    std::vector<std::string> outputs, zero;
    for (const OutputSpec& o : method->Outputs()) outputs.push_back(Quote(o.name));
    std::string windup = "null";
    if (const std::optional<WindupLaw> law = method->Windup()) {
      for (const char* option : law->only_when_zero) zero.push_back(Quote(option));
      windup = "{\"exponent\": " + Quote(law->exponent_option) +
               ", \"only_when_zero\": " + names(zero) + "}";
    }
    items.push_back("{\"type\": " + Quote(t.name) + ", \"family\": " + Quote(ToString(t.family)) +
                    ", \"outputs\": " + names(outputs) + ", \"windup\": " + windup + "}");
  }
  return List(items, indent);
}

}  // namespace

std::string SchemaJson(const RunConfig& config) {
  const bool rig = config.HasRig();
  std::vector<std::string> rule;
  for (const char* r : kNamingRule) rule.push_back(Quote(r));
  if (rig) rule.push_back(Quote(kRigNamingRule));
  std::vector<std::string> quantities;
  for (const MetricSpec& m : RunQuantities()) quantities.push_back(QuantityJson(m));
  // Rig runs: every per-row file, summary.csv and track_bands.csv end in a camera column; rig.csv.
  std::vector<std::pair<const char*, std::vector<ColumnInfo>>> files = {
      {"runs.csv", WithCameraColumn(RunRowColumns(), rig)},
      {"summary.csv", WithCameraColumn(SummaryColumns(), rig)},
      {"timings.csv", WithCameraColumn(TimingColumns(), rig)},
      {"curves.csv", WithCameraColumn(CurveColumns(), rig)},
      {"events.csv", WithCameraColumn(EventColumns(), rig)},
      {"tracks.csv", WithCameraColumn(TrackColumns(), rig)},
      {"track_errors.csv", WithCameraColumn(TrackErrorColumns(), rig)},
      {"track_bands.csv", WithCameraColumn(TrackBandColumns(), rig)}};
  if (rig) files.emplace_back("rig.csv", RigColumns());
  std::string out = "{\n  \"schema_version\": 1,\n  \"naming_rule\": " + List(rule, "  ") +
                    ",\n  \"quantities\": " + List(quantities, "  ") + ",\n  \"files\": {\n";
  for (size_t i = 0; i < std::size(files); ++i) {
    out += "    " + Quote(files[i].first) + ": " + FileJson(files[i].second, "    ") +
           (i + 1 < std::size(files) ? ",\n" : "\n");
  }
  out += "  },\n  \"sweeps\": " + SweepsJson(config, "  ") +
         ",\n  \"methods\": " + MethodsJson("  ") + "\n}\n";
  return out;
}

}  // namespace calibench
