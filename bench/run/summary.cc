#include "bench/run/summary.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>

#include "bench/run/csv.h"
#include "bench/run/stats.h"
#include "metrics/metric_table.h"

namespace calibench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Pair {
  std::string scenario, sweep, point, params, method;
  std::string camera;  // Rig runs (a camera column): the rows' camera; else empty.
  long n = 0, n_failed = 0;
  std::vector<std::vector<double>> values;  // Per metric: the ok rows' values.
  std::vector<std::vector<double>> crlb;    // Per metric: the rows' bounds (finite ones).
  std::vector<std::vector<double>> stds;    // Per metric: the ok rows' reported stds (finite).
};

// The summarised quantities of a run (the metric table's and the method outputs), in order.
const std::vector<const MetricSpec*>& Summarised() {
  static const std::vector<const MetricSpec*> specs = [] {
    std::vector<const MetricSpec*> out;
    for (const MetricSpec& m : RunQuantities()) {
      if (m.summary != Summary::kNone) out.push_back(&m);
    }
    return out;
  }();
  return specs;
}

std::vector<double> Absolute(const std::vector<double>& v) {
  std::vector<double> out;
  out.reserve(v.size());
  for (double x : v) out.push_back(std::abs(x));
  return out;
}

}  // namespace

const std::vector<std::string>& SummaryMetrics() {
  static const std::vector<std::string> metrics = [] {
    std::vector<std::string> out;
    for (const MetricSpec* m : Summarised()) out.push_back(SummaryColumn(*m));
    return out;
  }();
  return metrics;
}

const std::vector<ColumnInfo>& SummaryColumns() {
  static const std::vector<ColumnInfo> columns = {
      {"scenario", "", "scenario name"},
      {"sweep", "", "the swept scenario's name"},
      {"point", "", "sweep point"},
      {"params", "", "the sweep point's field=value;..."},
      {"method", "", "the method instance"},
      {"metric", "",
       "the runs.csv column summarised, unit included: the unit of every value column below"},
      {"n", "", "rows (trials) of the (scenario, method)"},
      {"n_failed", "", "rows whose status is not ok: left out of every statistic"},
      {"n_used", "", "ok rows with a finite value"},
      {"median", "", "median of the signed values"},
      {"mean", "", "mean of the signed values"},
      {"std", "", "standard deviation of the signed values (n - 1): the Monte Carlo spread"},
      {"p2_5", "", "2.5th percentile of the signed values (type 7)"},
      {"p97_5", "", "97.5th percentile of the signed values"},
      {"rmse", "", "sqrt(mean(value^2)), for the errors against the truth (Summary::kWithRmse)"},
      {"crlb", "", "median of the rows' Cramer-Rao std (crlb_Q), where the quantity has one"},
      {"rmse_over_crlb", "", "rmse / crlb: 1 at the bound"},
      {"median_abs", "", "median of |value|"},
      {"p2_5_abs", "", "2.5th percentile of |value|"},
      {"p97_5_abs", "", "97.5th percentile of |value|"},
      {"std_reported", "",
       "median of the ok rows' reported std (std_Q), where the quantity has one"},
  };
  return columns;
}

namespace {

// Where each field of runs.csv is: the keys, the status, and per summarised metric its value,
// its Cramer-Rao bound and its reported std (-1: not in the file).
struct RunsColumns {
  int scenario = -1, sweep = -1, point = -1, params = -1, method = -1, status = -1;
  int camera = -1;  // Rig runs only.
  std::vector<int> metric, crlb, std;
};
bool FindRunsColumns(const std::vector<std::string>& header, RunsColumns* cols) {
  auto column = [&](const std::string& name) -> int {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    return -1;
  };
  for (const MetricSpec* m : Summarised()) {
    cols->metric.push_back(column(SummaryColumn(*m)));
    cols->crlb.push_back(m->columns & kCrlbColumn ? column(ColumnName(*m, kCrlbColumn)) : -1);
    cols->std.push_back(m->columns & kStdColumn ? column(ColumnName(*m, kStdColumn)) : -1);
  }
  cols->scenario = column("scenario"), cols->sweep = column("sweep"), cols->point = column("point");
  cols->params = column("params"), cols->method = column("method"), cols->status = column("status");
  cols->camera = column(CameraColumn().name);
  for (int c :
       {cols->scenario, cols->sweep, cols->point, cols->params, cols->method, cols->status}) {
    if (c < 0) return false;
  }
  return true;
}

// One row of runs.csv into its (scenario, method) pair: the bounds of every trial, the values
// and stds of the trials that ended ok (finite ones only).
void AddRow(const std::vector<std::string>& fields, const RunsColumns& cols, Pair* p) {
  ++p->n;
  const bool ok = fields[cols.status] == "ok";
  if (!ok) ++p->n_failed;
  for (size_t m = 0; m < cols.metric.size(); ++m) {
    if (cols.crlb[m] >= 0) {
      const double b = std::strtod(fields[cols.crlb[m]].c_str(), nullptr);
      if (std::isfinite(b)) p->crlb[m].push_back(b);
    }
    if (!ok) continue;
    if (cols.std[m] >= 0) {
      const double s = std::strtod(fields[cols.std[m]].c_str(), nullptr);
      if (std::isfinite(s)) p->stds[m].push_back(s);
    }
    if (cols.metric[m] < 0) continue;
    const double v = std::strtod(fields[cols.metric[m]].c_str(), nullptr);
    if (std::isfinite(v)) p->values[m].push_back(v);
  }
}

// The rows of runs.csv grouped by (scenario, method), in first-seen order: per summarised metric
// the values of the ok rows, the CRLB of every row and the reported std of the ok rows. False with
// *why naming the file (unreadable, not a runs.csv, a record of the wrong width).
bool ReadPairs(const std::string& runs_csv, std::vector<Pair>* pairs_out, std::string* why) {
  std::ifstream in(runs_csv, std::ios::binary);
  if (!in) {
    if (why) *why = runs_csv + ": cannot open for reading";
    return false;
  }
  CsvReader reader(&in);
  std::vector<std::string> header, fields;
  std::string reason;
  if (!reader.Next(&header, &reason)) {
    if (why) *why = runs_csv + ": " + (reason.empty() ? "empty file (no header)" : reason);
    return false;
  }
  RunsColumns cols;
  if (!FindRunsColumns(header, &cols)) {
    if (why) *why = runs_csv + ": not a calibench runs.csv (a key column is missing)";
    return false;
  }
  const size_t num_metrics = SummaryMetrics().size();
  std::vector<Pair>& pairs = *pairs_out;
  pairs.clear();
  std::map<std::vector<std::string>, size_t> index;
  while (reader.Next(&fields, &reason)) {
    if (fields.size() != header.size()) {
      if (why) {
        *why = runs_csv + ": record " + std::to_string(reader.record()) + ": " +
               std::to_string(fields.size()) + " fields, the header has " +
               std::to_string(header.size());
      }
      return false;
    }
    std::vector<std::string> key = {fields[cols.scenario], fields[cols.method]};
    if (cols.camera >= 0) key.push_back(fields[cols.camera]);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, pairs.size()).first;
      Pair p;
      p.scenario = fields[cols.scenario];
      p.sweep = fields[cols.sweep];
      p.point = fields[cols.point];
      p.params = fields[cols.params];
      p.method = fields[cols.method];
      if (cols.camera >= 0) p.camera = fields[cols.camera];
      p.values.resize(num_metrics);
      p.crlb.resize(num_metrics);
      p.stds.resize(num_metrics);
      pairs.push_back(std::move(p));
    }
    AddRow(fields, cols, &pairs[it->second]);
  }
  if (!reason.empty()) {
    if (why) *why = runs_csv + ": " + reason;
    return false;
  }
  return true;
}

// Metric m of pair p as one summary.csv line (SummaryColumns).
std::string SummaryLine(const Pair& p, size_t m) {
  const std::vector<std::string>& metrics = SummaryMetrics();
  const std::vector<double>& v = p.values[m];
  double mean = kNaN, std = kNaN, rmse = kNaN;
  if (!v.empty()) {
    double sum = 0, sum_sq = 0;
    for (double x : v) sum += x, sum_sq += x * x;
    mean = sum / v.size();
    if (v.size() > 1) {
      double ss = 0;
      for (double x : v) ss += (x - mean) * (x - mean);
      std = std::sqrt(ss / (v.size() - 1));
    }
    if (Summarised()[m]->summary == Summary::kWithRmse) rmse = std::sqrt(sum_sq / v.size());
  }
  const double crlb = Median(p.crlb[m]);
  const std::vector<double> a = Absolute(v);
  std::vector<std::string> fields = {p.scenario,
                                     p.sweep,
                                     p.point,
                                     p.params,
                                     p.method,
                                     metrics[m],
                                     std::to_string(p.n),
                                     std::to_string(p.n_failed),
                                     std::to_string(v.size()),
                                     FormatNumber(Median(v)),
                                     FormatNumber(mean),
                                     FormatNumber(std),
                                     FormatNumber(Quantile(v, 0.025)),
                                     FormatNumber(Quantile(v, 0.975)),
                                     FormatNumber(rmse),
                                     FormatNumber(crlb),
                                     FormatNumber(crlb > 0 ? rmse / crlb : kNaN),
                                     FormatNumber(Median(a)),
                                     FormatNumber(Quantile(a, 0.025)),
                                     FormatNumber(Quantile(a, 0.975)),
                                     FormatNumber(Median(p.stds[m]))};
  if (!p.camera.empty()) fields.push_back(p.camera);
  return CsvLine(fields);
}

}  // namespace

bool SummarizeRuns(const std::string& runs_csv, std::string* summary_csv, std::string* why) {
  std::vector<Pair> pairs;
  if (!ReadPairs(runs_csv, &pairs, why)) return false;
  std::vector<std::string> out_header;
  for (const ColumnInfo& c : SummaryColumns()) out_header.push_back(c.name);
  const bool cameras = !pairs.empty() && !pairs.front().camera.empty();
  std::string out = CsvLine(WithCameraColumn(out_header, cameras));
  for (const Pair& p : pairs) {
    for (size_t m = 0; m < SummaryMetrics().size(); ++m) out += SummaryLine(p, m);
  }
  *summary_csv = std::move(out);
  return true;
}

const std::vector<ColumnInfo>& TrackBandColumns() {
  static const std::vector<ColumnInfo> columns = {
      {"scenario", "", "scenario name"},
      {"point", "", "sweep point"},
      {"method", "", "the method instance"},
      {"t_s", "s", "report time"},
      {"quantity", "",
       "the tracked quantity, unit included (roll_deg, ..., v0_px), or nees, nees_rotation: the "
       "unit of the value columns"},
      {"n", "", "trials with a finite value"},
      {"mean", "", "mean of the signed errors (of NEES: the mean NEES)"},
      {"median", "", "median of the signed errors"},
      {"median_abs", "", "median of |error|"},
      {"p2_5", "", "2.5th percentile of the signed errors"},
      {"p97_5", "", "97.5th percentile of the signed errors"}};
  return columns;
}

bool SummarizeTrackErrors(const std::string& track_errors_csv, std::string* bands_csv,
                          std::string* why) {
  std::vector<std::string> header_out;
  for (const ColumnInfo& c : TrackBandColumns()) header_out.push_back(c.name);
  std::string out = CsvLine(header_out);
  std::ifstream in(track_errors_csv, std::ios::binary);
  if (!in) {
    *bands_csv = out;
    return true;
  }
  CsvReader reader(&in);
  std::vector<std::string> header, fields;
  std::string reason;
  if (!reader.Next(&header, &reason)) {
    *bands_csv = out;
    return true;
  }
  const int first_value = 5;  // scenario, point, trial, method, t_s, then the values.
  if (header.size() <= static_cast<size_t>(first_value)) {
    if (why) *why = track_errors_csv + ": not a calibench track_errors.csv";
    return false;
  }
  // Rig runs: a last camera column, a key (the bands are per camera).
  const bool cameras = header.back() == CameraColumn().name;
  const size_t end_value = header.size() - (cameras ? 1 : 0);
  if (cameras) out = CsvLine(WithCameraColumn(header_out, true));
  struct Key {
    std::string scenario, point, method, t_s, camera;
    std::vector<std::vector<double>> values;  // Per value column.
  };
  std::vector<Key> keys;
  std::map<std::vector<std::string>, size_t> index;
  while (reader.Next(&fields, &reason)) {
    if (fields.size() != header.size()) {
      if (why) *why = track_errors_csv + ": record " + std::to_string(reader.record()) + ": bad";
      return false;
    }
    const std::string camera = cameras ? fields.back() : "";
    const std::vector<std::string> id = {fields[0], fields[1], fields[3], fields[4], camera};
    auto it = index.find(id);
    if (it == index.end()) {
      it = index.emplace(id, keys.size()).first;
      keys.push_back({fields[0], fields[1], fields[3], fields[4], camera, {}});
      keys.back().values.resize(end_value - first_value);
    }
    for (size_t c = first_value; c < end_value; ++c) {
      const double v = std::strtod(fields[c].c_str(), nullptr);
      if (std::isfinite(v)) keys[it->second].values[c - first_value].push_back(v);
    }
  }
  if (!reason.empty()) {
    if (why) *why = track_errors_csv + ": " + reason;
    return false;
  }
  for (const Key& k : keys) {
    for (size_t c = 0; c < k.values.size(); ++c) {
      const std::vector<double>& v = k.values[c];
      std::string name = header[first_value + c];
      if (name.rfind("err_", 0) == 0) name = name.substr(4);
      double mean = kNaN;
      std::vector<double> abs_values;
      if (!v.empty()) {
        double sum = 0;
        for (double x : v) sum += x, abs_values.push_back(std::abs(x));
        mean = sum / v.size();
      }
      std::vector<std::string> line = {k.scenario,
                                       k.point,
                                       k.method,
                                       k.t_s,
                                       name,
                                       std::to_string(v.size()),
                                       FormatNumber(mean),
                                       FormatNumber(Median(v)),
                                       FormatNumber(Median(abs_values)),
                                       FormatNumber(Quantile(v, 0.025)),
                                       FormatNumber(Quantile(v, 0.975))};
      if (cameras) line.push_back(k.camera);
      out += CsvLine(line);
    }
  }
  *bands_csv = std::move(out);
  return true;
}

}  // namespace calibench
