#include "bench/run/run_row.h"

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <type_traits>

#include "bench/run/csv.h"
#include "core/format.h"

namespace calibench {
namespace {

// One runs.csv column: its name, how to write it and how to read it back.
struct Column {
  std::string name;
  std::function<std::string(const RunRow&)> get;
  std::function<bool(const std::string&, RunRow*)> set;
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

Column Num(const char* name, double RunRow::*field) {
  return {name, [field](const RunRow& r) { return FormatNumber(r.*field); },
          [field](const std::string& t, RunRow* r) { return ParseDouble(t, &(r->*field)); }};
}
template <typename Integer>
Column Int(const char* name, Integer RunRow::*field) {
  return {name, [field](const RunRow& r) { return std::to_string(r.*field); },
          [field](const std::string& t, RunRow* r) { return ParseInt(t, &(r->*field)); }};
}
Column Text(const char* name, std::string RunRow::*field) {
  return {name, [field](const RunRow& r) { return r.*field; },
          [field](const std::string& t, RunRow* r) {
            r->*field = t;
            return true;
          }};
}

// The CSV schema, in order: one entry per column.
const std::vector<Column>& Columns() {
  static const std::vector<Column> columns = {
      Text("scenario", &RunRow::scenario),
      Text("sweep", &RunRow::sweep),
      Int("point", &RunRow::point),
      Text("params", &RunRow::params),
      Int("n_points", &RunRow::n_points),
      Int("trial", &RunRow::trial),
      Int("seed", &RunRow::seed),
      Text("method", &RunRow::method),
      Text("status", &RunRow::status),
      Num("fku", &RunRow::fku),
      Num("fkv", &RunRow::fkv),
      Num("phi_deg", &RunRow::phi_deg),
      Num("u0", &RunRow::u0),
      Num("v0", &RunRow::v0),
      Num("rc_roll_deg", &RunRow::rc_roll_deg),
      Num("rc_pitch_deg", &RunRow::rc_pitch_deg),
      Num("rc_yaw_deg", &RunRow::rc_yaw_deg),
      Num("xc_x", &RunRow::xc_x),
      Num("xc_y", &RunRow::xc_y),
      Num("xc_z", &RunRow::xc_z),
      Num("err_fku", &RunRow::err_fku),
      Num("err_fkv", &RunRow::err_fkv),
      Num("err_phi_deg", &RunRow::err_phi_deg),
      Num("err_u0", &RunRow::err_u0),
      Num("err_v0", &RunRow::err_v0),
      Num("rot_err_deg", &RunRow::rot_err_deg),
      Num("err_xc_norm", &RunRow::err_xc_norm),
      Num("theta_err_norm", &RunRow::theta_err_norm),
      Num("rms_reproj_px", &RunRow::rms_reproj_px),
      Num("converge_time_s", &RunRow::converge_time_s),
      Num("pe_min_eig", &RunRow::pe_min_eig),
      Num("ortho_defect", &RunRow::ortho_defect),
      Num("std_fku", &RunRow::std_fku),
      Num("std_fkv", &RunRow::std_fkv),
      Num("std_phi_deg", &RunRow::std_phi_deg),
      Num("std_u0", &RunRow::std_u0),
      Num("std_v0", &RunRow::std_v0),
      Num("crlb_fku", &RunRow::crlb_fku),
      Num("crlb_fkv", &RunRow::crlb_fkv),
      Num("crlb_phi_deg", &RunRow::crlb_phi_deg),
      Num("crlb_u0", &RunRow::crlb_u0),
      Num("crlb_v0", &RunRow::crlb_v0),
      Int("improper", &RunRow::improper),
      Int("steps", &RunRow::steps),
      Num("detect_rate", &RunRow::detect_rate),
      Num("corner_rms_px", &RunRow::corner_rms_px),
      Int("frames_no_detection", &RunRow::frames_no_detection),
      Text("message", &RunRow::message),
      Num("err_roll_deg", &RunRow::err_roll_deg),
      Num("err_pitch_deg", &RunRow::err_pitch_deg),
      Num("err_yaw_deg", &RunRow::err_yaw_deg),
      Int("n_frames_used", &RunRow::n_frames_used),
      Int("n_obs_used", &RunRow::n_obs_used),
      Num("corner_radial_bias_px", &RunRow::corner_radial_bias_px),
      Num("corner_crlb_px", &RunRow::corner_crlb_px),
  };
  return columns;
}

}  // namespace

const std::vector<std::string>& RunRowHeader() {
  static const std::vector<std::string> header = [] {
    std::vector<std::string> names;
    for (const Column& c : Columns()) names.push_back(c.name);
    return names;
  }();
  return header;
}

std::vector<std::string> RunRowFields(const RunRow& r) {
  std::vector<std::string> fields;
  fields.reserve(Columns().size());
  for (const Column& c : Columns()) fields.push_back(c.get(r));
  return fields;
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
    for (const Column& c : Columns()) {
      if (c.name != header[i]) continue;
      if (!c.set(fields[i], row)) {
        if (why) *why = "column " + c.name + ": cannot read '" + fields[i] + "'";
        return false;
      }
    }
  }
  return true;
}

const std::vector<std::string>& TimingHeader() {
  static const std::vector<std::string> header = {"scenario",   "trial",  "method",      "wall_ms",
                                                  "measure_ms", "reused", "us_per_frame"};
  return header;
}

std::vector<std::string> TimingFields(const RunRow& r) {
  const double per_frame = r.frames > 0 ? 1000.0 * r.wall_ms / r.frames : kUnset;
  return {r.scenario,
          std::to_string(r.trial),
          r.method,
          FormatNumber(r.wall_ms),
          FormatNumber(r.measure_ms),
          r.reused ? "1" : "0",
          FormatNumber(per_frame)};
}

const std::vector<std::string>& EventHeader() {
  static const std::vector<std::string> header = {"scenario",     "point",      "trial",   "method",
                                                  "event",        "quantity",   "at_s",    "tol",
                                                  "reconverge_s", "steady_err", "peak_err"};
  return header;
}

namespace {

std::vector<std::string> TrackHeaderOf(bool estimates_and_truth) {
  std::vector<std::string> header = {"scenario", "point", "trial", "method", "t_s"};
  for (const char* q : TrackQuantityNames()) {
    if (estimates_and_truth) {
      header.push_back(std::string("est_") + q);
      header.push_back(std::string("true_") + q);
    } else {
      header.push_back(std::string("err_") + q);
    }
  }
  header.push_back("nees");
  header.push_back("nees_rotation");
  return header;
}

std::vector<std::string> RowKey(const RunRow& r) {
  return {r.scenario, std::to_string(r.point), std::to_string(r.trial), r.method};
}

}  // namespace

const std::vector<std::string>& TrackHeader() {
  static const std::vector<std::string> header = TrackHeaderOf(true);
  return header;
}

const std::vector<std::string>& TrackErrorHeader() {
  static const std::vector<std::string> header = TrackHeaderOf(false);
  return header;
}

std::string EventLines(const RunRow& r) {
  std::string text;
  for (const EventMetrics& e : r.events) {
    std::vector<std::string> fields = RowKey(r);
    fields.insert(fields.end(),
                  {std::to_string(e.event), TrackQuantityNames()[e.quantity], FormatNumber(e.at_s),
                   FormatNumber(e.tol), FormatNumber(e.reconverge_s), FormatNumber(e.steady_err),
                   FormatNumber(e.peak_err)});
    text += CsvLine(fields);
  }
  return text;
}

std::string TrackLines(const RunRow& r) {
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
    text += CsvLine(fields);
  }
  return text;
}

std::string TrackErrorLines(const RunRow& r, int band_samples) {
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
    text += CsvLine(fields);
  }
  return text;
}

const std::vector<std::string>& CurveHeader() {
  static const std::vector<std::string> header = {"scenario", "trial", "method", "t_s",
                                                  "theta_err_norm"};
  return header;
}

}  // namespace calibench
