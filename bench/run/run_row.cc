#include "bench/run/run_row.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <type_traits>

#include "bench/run/csv.h"
#include "methods/registry.h"
#include "metrics/metric_table.h"
#include "util/format.h"

namespace calibench {
namespace {

// One runs.csv column: its name, unit and doc (the metric table's for a quantity), how to write it
// and how to read it back; for a quantity's column, which one it is.
struct Column {
  ColumnInfo info;
  std::function<std::string(const RunRow&)> get;
  std::function<bool(const std::string&, RunRow*)> set;
  const MetricSpec* metric = nullptr;
  MetricColumn kind = kValueColumn;
};

bool ParseDouble(const std::string& text, double* v) {
  if (text == "nan") {
    *v = kUnset;
    return true;
  }
  char* end = nullptr;
  *v = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size();
}

template <typename Int>
bool ParseInt(const std::string& text, Int* v) {
  char* end = nullptr;
  if (text.empty()) return false;
  if constexpr (std::is_unsigned_v<Int>) {
    *v = static_cast<Int>(std::strtoull(text.c_str(), &end, 10));
  } else {
    *v = static_cast<Int>(std::strtoll(text.c_str(), &end, 10));
  }
  return end == text.c_str() + text.size();
}

// A key or text column (not a quantity): its name and doc are given here.
Column Text(const char* name, const char* doc, std::string RunRow::*field) {
  return {{name, "", doc},
          [field](const RunRow& r) { return r.*field; },
          [field](const std::string& t, RunRow* r) {
            r->*field = t;
            return true;
          }};
}
template <typename Integer>
Column Key(const char* name, const char* doc, Integer RunRow::*field) {
  return {{name, "", doc},
          [field](const RunRow& r) { return std::to_string(r.*field); },
          [field](const std::string& t, RunRow* r) { return ParseInt(t, &(r->*field)); }};
}

// A column of a quantity of the metric table (its name, unit and doc come from there).
Column Of(Metric metric, MetricColumn kind, double RunRow::*field) {
  const MetricSpec& spec = Spec(metric);
  return {{ColumnName(metric, kind), spec.unit, ColumnDoc(spec, kind)},
          [field](const RunRow& r) { return FormatNumber(r.*field); },
          [field](const std::string& t, RunRow* r) { return ParseDouble(t, &(r->*field)); },
          &spec,
          kind};
}
template <typename Integer>
Column Count(Metric metric, Integer RunRow::*field) {
  const MetricSpec& spec = Spec(metric);
  return {{spec.name, spec.unit, spec.doc},
          [field](const RunRow& r) { return std::to_string(r.*field); },
          [field](const std::string& t, RunRow* r) { return ParseInt(t, &(r->*field)); },
          &spec,
          kValueColumn};
}

// The place of the declared method outputs in the layout: ExpandMethodOutputs replaces it by their
// columns, in RunQuantities order (an output a row lacks: NaN).
Column MethodOutputsSlot() {
  Column slot;
  slot.kind = MetricColumn{};  // No column kind: the marker ExpandMethodOutputs looks for.
  return slot;
}

Column MethodOutput(const MetricSpec& spec) {
  const std::string name = spec.name;
  return {{name, spec.unit, spec.doc},
          [name](const RunRow& r) {
            const auto it = r.method_outputs.find(name);
            return FormatNumber(it == r.method_outputs.end() ? kUnset : it->second);
          },
          [name](const std::string& t, RunRow* r) {
            double v = kUnset;
            if (!ParseDouble(t, &v)) return false;
            if (std::isnan(v)) {
              r->method_outputs.erase(name);
            } else {
              r->method_outputs[name] = v;
            }
            return true;
          },
          &spec,
          kValueColumn};
}

// The slot follows the value column of kMethodOutputsAfter, as the outputs follow that quantity
// in RunQuantities (a programmer error otherwise).
std::vector<Column> ExpandMethodOutputs(std::vector<Column> laid_out) {
  std::vector<Column> out;
  for (Column& c : laid_out) {
    if (c.kind != MetricColumn{}) {
      out.push_back(std::move(c));
      continue;
    }
    if (out.empty() || out.back().metric == nullptr ||
        out.back().metric->id != kMethodOutputsAfter) {
      throw std::logic_error("runs.csv layout: the method outputs' slot is not after " +
                             std::string(Spec(kMethodOutputsAfter).name));
    }
    for (const MetricSpec& spec : RunQuantities()) {
      if (spec.id == Metric::kMethodOutput) out.push_back(MethodOutput(spec));
    }
  }
  return out;
}

// Every column of the quantities of a run that runs.csv carries is in the layout once (a
// programmer error otherwise: the quantities and the layout disagree).
void CheckAgainstTheTable(const std::vector<Column>& columns) {
  for (const MetricSpec& spec : RunQuantities()) {
    for (MetricColumn kind : {kValueColumn, kErrorColumn, kStdColumn, kCrlbColumn}) {
      const bool declared = (spec.columns & kind) != 0;
      const long laid_out = std::count_if(columns.begin(), columns.end(), [&](const Column& c) {
        return c.metric != nullptr && std::string(c.metric->name) == spec.name && c.kind == kind;
      });
      if (laid_out != (declared ? 1 : 0)) {
        throw std::logic_error("runs.csv layout: " + std::string(spec.name) + " (column kind " +
                               std::to_string(kind) + ") is laid out " + std::to_string(laid_out) +
                               " times");
      }
    }
  }
}

// The runs.csv layout, in file order (columns are only ever appended; the method outputs' slot
// after converge_time_s grows with the registry).
const std::vector<Column>& Columns() {
  using M = Metric;
  static const std::vector<Column> columns = [] {
    std::vector<Column> c = {
        Text("scenario", "scenario name; a sweep point is NAME[field=value,...]",
             &RunRow::scenario),
        Text("sweep", "the swept scenario's name (the scenario's own when not swept)",
             &RunRow::sweep),
        Key("point", "position of the sweep point in the sweep's product", &RunRow::point),
        Text("params", "the sweep point's field=value;... (empty when not swept)", &RunRow::params),
        Key("n_points", "feature points of the scenario (all boards' corners)", &RunRow::n_points),
        Key("trial", "Monte Carlo trial", &RunRow::trial),
        Key("seed", "the trial's seed (rows with equal seeds saw the same measurements)",
            &RunRow::seed),
        Text("method", "the method instance", &RunRow::method),
        Text("status", "ok | diverged | failed", &RunRow::status),
        Of(M::kFku, kValueColumn, &RunRow::fku_px),
        Of(M::kFkv, kValueColumn, &RunRow::fkv_px),
        Of(M::kPhi, kValueColumn, &RunRow::phi_deg),
        Of(M::kU0, kValueColumn, &RunRow::u0_px),
        Of(M::kV0, kValueColumn, &RunRow::v0_px),
        Of(M::kRoll, kValueColumn, &RunRow::roll_deg),
        Of(M::kPitch, kValueColumn, &RunRow::pitch_deg),
        Of(M::kYaw, kValueColumn, &RunRow::yaw_deg),
        Of(M::kXcX, kValueColumn, &RunRow::xc_x_m),
        Of(M::kXcY, kValueColumn, &RunRow::xc_y_m),
        Of(M::kXcZ, kValueColumn, &RunRow::xc_z_m),
        Of(M::kFku, kErrorColumn, &RunRow::err_fku_px),
        Of(M::kFkv, kErrorColumn, &RunRow::err_fkv_px),
        Of(M::kPhi, kErrorColumn, &RunRow::err_phi_deg),
        Of(M::kU0, kErrorColumn, &RunRow::err_u0_px),
        Of(M::kV0, kErrorColumn, &RunRow::err_v0_px),
        Of(M::kRotErr, kValueColumn, &RunRow::rot_err_deg),
        Of(M::kXcErr, kValueColumn, &RunRow::xc_err_m),
        Of(M::kThetaErr, kValueColumn, &RunRow::theta_err_norm),
        Of(M::kRmsReproj, kValueColumn, &RunRow::rms_reproj_px),
        Of(M::kConvergeTime, kValueColumn, &RunRow::converge_time_s),
        MethodOutputsSlot(),  // The declared method outputs (pe_min_eig).
        Of(M::kOrthoDefect, kValueColumn, &RunRow::ortho_defect),
        Of(M::kFku, kStdColumn, &RunRow::std_fku_px),
        Of(M::kFkv, kStdColumn, &RunRow::std_fkv_px),
        Of(M::kPhi, kStdColumn, &RunRow::std_phi_deg),
        Of(M::kU0, kStdColumn, &RunRow::std_u0_px),
        Of(M::kV0, kStdColumn, &RunRow::std_v0_px),
        Of(M::kFku, kCrlbColumn, &RunRow::crlb_fku_px),
        Of(M::kFkv, kCrlbColumn, &RunRow::crlb_fkv_px),
        Of(M::kPhi, kCrlbColumn, &RunRow::crlb_phi_deg),
        Of(M::kU0, kCrlbColumn, &RunRow::crlb_u0_px),
        Of(M::kV0, kCrlbColumn, &RunRow::crlb_v0_px),
        Count(M::kImproper, &RunRow::improper),
        Count(M::kSteps, &RunRow::steps),
        Of(M::kDetectRate, kValueColumn, &RunRow::detect_rate),
        Of(M::kCornerRms, kValueColumn, &RunRow::corner_rms_px),
        Count(M::kFramesNoDetection, &RunRow::frames_no_detection),
        Text("message", "why a row failed, or a warning", &RunRow::message),
        Of(M::kRoll, kErrorColumn, &RunRow::err_roll_deg),
        Of(M::kPitch, kErrorColumn, &RunRow::err_pitch_deg),
        Of(M::kYaw, kErrorColumn, &RunRow::err_yaw_deg),
        Count(M::kFramesUsed, &RunRow::n_frames_used),
        Count(M::kObsUsed, &RunRow::n_obs_used),
        Of(M::kCornerRadialBias, kValueColumn, &RunRow::corner_radial_bias_px),
        Of(M::kCornerCrlb, kValueColumn, &RunRow::corner_crlb_px),
        Of(M::kProjErr, kValueColumn, &RunRow::proj_err_px),
        Of(M::kProjErrRatio, kValueColumn, &RunRow::proj_err_ratio),
    };
    c = ExpandMethodOutputs(std::move(c));
    CheckAgainstTheTable(c);
    return c;
  }();
  return columns;
}

}  // namespace

const std::vector<MetricSpec>& RunQuantities() {
  static const std::vector<MetricSpec> quantities = [] {
    std::vector<MetricSpec> out;
    for (const MetricSpec& m : MetricTable()) {
      out.push_back(m);
      if (m.id != kMethodOutputsAfter) continue;
      for (const OutputSpec& o : DeclaredOutputs()) {
        MetricSpec spec;
        spec.id = Metric::kMethodOutput;
        spec.name = o.name;
        spec.unit = o.unit;
        spec.label = o.label;
        spec.doc = o.doc;
        spec.summary =
            o.summary == OutputSummary::kStatistics ? Summary::kStatistics : Summary::kNone;
        out.push_back(spec);
      }
    }
    return out;
  }();
  return quantities;
}

const std::vector<ColumnInfo>& RunRowColumns() {
  static const std::vector<ColumnInfo> infos = [] {
    std::vector<ColumnInfo> out;
    for (const Column& c : Columns()) out.push_back(c.info);
    return out;
  }();
  return infos;
}

const std::vector<std::string>& RunRowHeader() {
  static const std::vector<std::string> header = [] {
    std::vector<std::string> names;
    for (const Column& c : Columns()) names.push_back(c.info.name);
    return names;
  }();
  return header;
}

std::vector<std::string> RunRowFields(const RunRow& r, bool camera_column) {
  std::vector<std::string> fields;
  fields.reserve(Columns().size() + 1);
  for (const Column& c : Columns()) fields.push_back(c.get(r));
  if (camera_column) fields.push_back(std::to_string(r.camera));
  return fields;
}

ColumnInfo CameraColumn() {
  return {"camera", "",
          "rig runs: the row's camera, its index in the scenario's rig.cameras (0: camera 0, the "
          "truth camera, and the camera of a scenario without rig)"};
}

std::vector<ColumnInfo> WithCameraColumn(std::vector<ColumnInfo> columns, bool camera_column) {
  if (camera_column) columns.push_back(CameraColumn());
  return columns;
}

std::vector<std::string> WithCameraColumn(std::vector<std::string> header, bool camera_column) {
  if (camera_column) header.push_back(CameraColumn().name);
  return header;
}

bool ParseRunRow(const std::vector<std::string>& header, const std::vector<std::string>& fields,
                 RunRow* row, std::string* why) {
  if (header.size() != fields.size()) {
    if (why)
      *why = std::to_string(fields.size()) + " fields, the header has " +
             std::to_string(header.size());
    return false;
  }
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == CameraColumn().name && !ParseInt(fields[i], &row->camera)) {
      if (why) *why = "column camera: cannot read '" + fields[i] + "'";
      return false;
    }
    for (const Column& c : Columns()) {
      if (c.info.name != header[i]) continue;
      if (!c.set(fields[i], row)) {
        if (why) *why = "column " + c.info.name + ": cannot read '" + fields[i] + "'";
        return false;
      }
    }
  }
  return true;
}

namespace {

std::vector<std::string> NamesOf(const std::vector<ColumnInfo>& columns) {
  std::vector<std::string> names;
  names.reserve(columns.size());
  for (const ColumnInfo& c : columns) names.push_back(c.name);
  return names;
}

// The key columns of the tracking files.
std::vector<ColumnInfo> TrackKeyColumns() {
  return {{"scenario", "", "scenario name"},
          {"point", "", "sweep point"},
          {"trial", "", "Monte Carlo trial"},
          {"method", "", "the method instance"}};
}

}  // namespace

const std::vector<ColumnInfo>& TimingColumns() {
  static const std::vector<ColumnInfo> columns = {
      {"scenario", "", "scenario name"},
      {"trial", "", "Monte Carlo trial"},
      {"method", "", "the method instance"},
      {"wall_ms", "ms", "the method's own wall time (0 when its row was copied)"},
      {"measure_ms", "ms", "producing the trial's measurements (render + detect), per task"},
      {"reused", "", "1: the row was copied from an earlier point with equal settings"},
      {"wall_per_frame_us", "us", "the method's wall time per frame of the trial"}};
  return columns;
}

const std::vector<ColumnInfo>& CurveColumns() {
  static const std::vector<ColumnInfo> columns = {
      {"scenario", "", "scenario name"},
      {"trial", "", "Monte Carlo trial"},
      {"method", "", "the method instance"},
      {"t_s", "s", "time"},
      {"theta_err_norm", "", Spec(Metric::kThetaErr).doc}};
  return columns;
}

const std::vector<std::string>& TimingHeader() {
  static const std::vector<std::string> header = NamesOf(TimingColumns());
  return header;
}

std::vector<std::string> TimingFields(const RunRow& r, bool camera_column) {
  const double per_frame = r.frames > 0 ? 1000.0 * r.wall_ms / r.frames : kUnset;
  std::vector<std::string> fields = {r.scenario,
                                     std::to_string(r.trial),
                                     r.method,
                                     FormatNumber(r.wall_ms),
                                     FormatNumber(r.measure_ms),
                                     r.reused ? "1" : "0",
                                     FormatNumber(per_frame)};
  if (camera_column) fields.push_back(std::to_string(r.camera));
  return fields;
}

const std::vector<ColumnInfo>& EventColumns() {
  static const std::vector<ColumnInfo> columns = [] {
    std::vector<ColumnInfo> c = TrackKeyColumns();
    c.insert(c.end(),
             {{"event", "", "0: the start; k: truth change k - 1"},
              {"quantity", "",
               "the tracked quantity, unit included (roll_deg, ..., v0_px): the unit of tol, "
               "steady_err and peak_err"},
              {"at_s", "s", "time of the event"},
              {"tol", "", "re-convergence tolerance, in the quantity's unit"},
              {"reconverge_s", "s",
               "first time after the event from which |error| stays within tol until the next "
               "event (NaN: never)"},
              {"steady_err", "", "median |error| over the last steady_fraction of the segment"},
              {"peak_err", "", "max |error| over the segment"}});
    return c;
  }();
  return columns;
}

const std::vector<std::string>& EventHeader() {
  static const std::vector<std::string> header = NamesOf(EventColumns());
  return header;
}

namespace {

std::vector<ColumnInfo> TrackColumnsOf(bool estimates_and_truth) {
  std::vector<ColumnInfo> columns = TrackKeyColumns();
  columns.push_back({"t_s", "s", "report time"});
  for (int q = 0; q < kTrackQuantities; ++q) {  // In TrackValues order.
    for (const MetricSpec& m : MetricTable()) {
      if (m.track != q) continue;
      const std::string name = m.name;
      if (estimates_and_truth) {
        columns.push_back({"est_" + name, m.unit, std::string(m.label) + ", the estimate"});
        columns.push_back({"true_" + name, m.unit, std::string(m.label) + ", the truth"});
      } else {
        columns.push_back({"err_" + name, m.unit, ColumnDoc(m, kErrorColumn)});
      }
    }
  }
  columns.push_back({"nees", "",
                     "e^T P^-1 e on [f*ku, f*kv, u0, v0, dtheta] (7 dof; NaN: no "
                     "covariance)"});
  columns.push_back({"nees_rotation", "", "e^T P^-1 e on dtheta (3 dof)"});
  return columns;
}

std::vector<std::string> RowKey(const RunRow& r) {
  return {r.scenario, std::to_string(r.point), std::to_string(r.trial), r.method};
}

}  // namespace

const std::vector<ColumnInfo>& TrackColumns() {
  static const std::vector<ColumnInfo> columns = TrackColumnsOf(true);
  return columns;
}

const std::vector<ColumnInfo>& TrackErrorColumns() {
  static const std::vector<ColumnInfo> columns = TrackColumnsOf(false);
  return columns;
}

const std::vector<std::string>& TrackHeader() {
  static const std::vector<std::string> header = NamesOf(TrackColumns());
  return header;
}

const std::vector<std::string>& TrackErrorHeader() {
  static const std::vector<std::string> header = NamesOf(TrackErrorColumns());
  return header;
}

std::string EventLines(const RunRow& r, bool camera_column) {
  std::string text;
  for (const EventMetrics& e : r.events) {
    std::vector<std::string> fields = RowKey(r);
    fields.insert(fields.end(),
                  {std::to_string(e.event), TrackQuantityNames()[e.quantity], FormatNumber(e.at_s),
                   FormatNumber(e.tol), FormatNumber(e.reconverge_s), FormatNumber(e.steady_err),
                   FormatNumber(e.peak_err)});
    if (camera_column) fields.push_back(std::to_string(r.camera));
    text += CsvLine(fields);
  }
  return text;
}

std::string TrackLines(const RunRow& r, bool camera_column) {
  std::string text;
  for (const TrackPoint& p : r.track) {
    std::vector<std::string> fields = RowKey(r);
    fields.push_back(FormatNumber(p.t_s));
    for (int q = 0; q < kTrackQuantities; ++q) {
      fields.push_back(FormatNumber(p.estimate[q]));
      fields.push_back(FormatNumber(p.truth[q]));
    }
    fields.push_back(FormatNumber(p.nees));
    fields.push_back(FormatNumber(p.nees_rotation));
    if (camera_column) fields.push_back(std::to_string(r.camera));
    text += CsvLine(fields);
  }
  return text;
}

std::string TrackErrorLines(const RunRow& r, int band_samples, bool camera_column) {
  std::string text;
  const size_t n = r.track.size();
  if (n == 0) return text;
  const size_t stride = std::max<size_t>(1, (n + band_samples - 1) / band_samples);
  for (size_t i = 0; i < n; i += stride) {
    const size_t k = i + stride >= n ? n - 1 : i;  // The last block ends on the last sample.
    const TrackPoint& p = r.track[k];
    std::vector<std::string> fields = RowKey(r);
    fields.push_back(FormatNumber(p.t_s));
    for (int q = 0; q < kTrackQuantities; ++q) fields.push_back(FormatNumber(p.error[q]));
    fields.push_back(FormatNumber(p.nees));
    fields.push_back(FormatNumber(p.nees_rotation));
    if (camera_column) fields.push_back(std::to_string(r.camera));
    text += CsvLine(fields);
  }
  return text;
}

const std::vector<std::string>& CurveHeader() {
  static const std::vector<std::string> header = NamesOf(CurveColumns());
  return header;
}

const std::vector<std::string>& RigHeader() {
  static const std::vector<std::string> header = NamesOf(RigColumns());
  return header;
}

}  // namespace calibench
