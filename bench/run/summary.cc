#include "bench/run/summary.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>

#include "bench/run/csv.h"
#include "bench/run/stats.h"

namespace calibench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The crlb_* column of an err_* metric, or "" when it has none.
std::string CrlbColumn(const std::string& metric) {
  for (const char* name : {"fku", "fkv", "phi_deg", "u0", "v0"}) {
    if (metric == std::string("err_") + name) return std::string("crlb_") + name;
  }
  return "";
}

struct Pair {
  std::string scenario, sweep, point, params, method;
  long n = 0, n_failed = 0;
  std::vector<std::vector<double>> values;  // Per metric: the ok rows' values.
  std::vector<std::vector<double>> crlb;    // Per metric: the rows' bounds (finite ones).
};

}  // namespace

const std::vector<std::string>& SummaryMetrics() {
  static const std::vector<std::string> metrics = {
      "theta_err_norm", "err_fku",     "err_fkv",     "err_phi_deg",   "err_u0",
      "err_v0",         "rot_err_deg", "err_xc_norm", "rms_reproj_px", "converge_time_s"};
  return metrics;
}

bool SummarizeRuns(const std::string& runs_csv, std::string* summary_csv, std::string* why) {
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
  auto column = [&](const std::string& name) -> int {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    return -1;
  };
  const std::vector<std::string>& metrics = SummaryMetrics();
  std::vector<int> metric_col, crlb_col;
  for (const std::string& m : metrics) {
    metric_col.push_back(column(m));
    crlb_col.push_back(CrlbColumn(m).empty() ? -1 : column(CrlbColumn(m)));
  }
  const int c_scenario = column("scenario"), c_sweep = column("sweep"), c_point = column("point"),
            c_params = column("params"), c_method = column("method"), c_status = column("status");
  for (int c : {c_scenario, c_sweep, c_point, c_params, c_method, c_status}) {
    if (c < 0) {
      if (why) *why = runs_csv + ": not a calibench runs.csv (a key column is missing)";
      return false;
    }
  }
  std::vector<Pair> pairs;
  std::map<std::pair<std::string, std::string>, size_t> index;
  while (reader.Next(&fields, &reason)) {
    if (fields.size() != header.size()) {
      if (why) {
        *why = runs_csv + ": record " + std::to_string(reader.record()) + ": " +
               std::to_string(fields.size()) + " fields, the header has " +
               std::to_string(header.size());
      }
      return false;
    }
    const auto key = std::make_pair(fields[c_scenario], fields[c_method]);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, pairs.size()).first;
      Pair p;
      p.scenario = fields[c_scenario];
      p.sweep = fields[c_sweep];
      p.point = fields[c_point];
      p.params = fields[c_params];
      p.method = fields[c_method];
      p.values.resize(metrics.size());
      p.crlb.resize(metrics.size());
      pairs.push_back(std::move(p));
    }
    Pair& p = pairs[it->second];
    ++p.n;
    const bool ok = fields[c_status] == "ok";
    if (!ok) ++p.n_failed;
    for (size_t m = 0; m < metrics.size(); ++m) {
      if (crlb_col[m] >= 0) {
        const double b = std::strtod(fields[crlb_col[m]].c_str(), nullptr);
        if (std::isfinite(b)) p.crlb[m].push_back(b);
      }
      if (!ok || metric_col[m] < 0) continue;
      const double v = std::strtod(fields[metric_col[m]].c_str(), nullptr);
      if (std::isfinite(v)) p.values[m].push_back(v);
    }
  }
  if (!reason.empty()) {
    if (why) *why = runs_csv + ": " + reason;
    return false;
  }
  std::string out = CsvLine({"scenario", "sweep", "point", "params", "method", "metric", "n",
                             "n_failed", "n_used", "median", "mean", "std", "p2_5", "p97_5", "rmse",
                             "crlb", "rmse_over_crlb"});
  for (const Pair& p : pairs) {
    for (size_t m = 0; m < metrics.size(); ++m) {
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
        if (metrics[m].rfind("err_", 0) == 0) rmse = std::sqrt(sum_sq / v.size());
      }
      const double crlb = Median(p.crlb[m]);
      out += CsvLine({p.scenario, p.sweep, p.point, p.params, p.method, metrics[m],
                      std::to_string(p.n), std::to_string(p.n_failed), std::to_string(v.size()),
                      FormatNumber(Median(v)), FormatNumber(mean), FormatNumber(std),
                      FormatNumber(Quantile(v, 0.025)), FormatNumber(Quantile(v, 0.975)),
                      FormatNumber(rmse), FormatNumber(crlb),
                      FormatNumber(crlb > 0 ? rmse / crlb : kNaN)});
    }
  }
  *summary_csv = std::move(out);
  return true;
}

bool SummarizeTrackErrors(const std::string& track_errors_csv, std::string* bands_csv,
                          std::string* why) {
  std::string out = CsvLine({"scenario", "point", "method", "t_s", "quantity", "n", "mean",
                             "median", "median_abs", "p2_5", "p97_5"});
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
  struct Key {
    std::string scenario, point, method, t_s;
    std::vector<std::vector<double>> values;  // Per value column.
  };
  std::vector<Key> keys;
  std::map<std::vector<std::string>, size_t> index;
  while (reader.Next(&fields, &reason)) {
    if (fields.size() != header.size()) {
      if (why) *why = track_errors_csv + ": record " + std::to_string(reader.record()) + ": bad";
      return false;
    }
    const std::vector<std::string> id = {fields[0], fields[1], fields[3], fields[4]};
    auto it = index.find(id);
    if (it == index.end()) {
      it = index.emplace(id, keys.size()).first;
      keys.push_back({fields[0], fields[1], fields[3], fields[4], {}});
      keys.back().values.resize(header.size() - first_value);
    }
    for (size_t c = first_value; c < header.size(); ++c) {
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
      out += CsvLine({k.scenario, k.point, k.method, k.t_s, name, std::to_string(v.size()),
                      FormatNumber(mean), FormatNumber(Median(v)), FormatNumber(Median(abs_values)),
                      FormatNumber(Quantile(v, 0.025)), FormatNumber(Quantile(v, 0.975))});
    }
  }
  *bands_csv = std::move(out);
  return true;
}

}  // namespace calibench
