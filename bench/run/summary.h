// summary.csv: the Monte Carlo summary of a runs.csv, one row per (scenario, method, metric), in
// the order the (scenario, method) pairs first appear, the metrics in the metric table's order
// (metrics/metric_table.h: the quantities whose Summary is not kNone; `metric` is the column
// summarised, err_Q or Q, whose unit every value column has). The percentile method of Algers
// 2018, §3.6: the 95% interval of a metric is [p2.5, p97.5] of its per-trial values (Quantile,
// type 7). The report reads these statistics; it computes none of them again.
//
// Columns (SummaryColumns): scenario, sweep, point, params, method, metric,
//   n         trials (rows) of the pair;
//   n_failed  rows whose status is not ok (diverged or failed): left out of every statistic;
//   n_used    ok rows with a finite value of the metric;
//   median, mean, std (n - 1), p2_5, p97_5   of the signed per-trial values;
//   rmse      sqrt(mean(value^2)) for the quantities summarised kWithRmse (the truth is the
//             reference: the signed errors and the position error);
//   crlb      the Cramer-Rao standard deviation of the parameter (median of the rows' crlb_Q);
//   rmse_over_crlb   1 at the bound (only for f*ku, f*kv, phi, u0, v0 with pixel noise alone);
//   median_abs, p2_5_abs, p97_5_abs   of |value| (the report's medians and 95% bands);
//   std_reported   median of the ok rows' reported standard deviations (std_Q).
// A summary depends on runs.csv alone, so the summary of merged shards equals an unsharded one.
#pragma once

#include <string>
#include <vector>

#include "bench/run/run_row.h"

namespace calibench {

// The metrics summarised, as runs.csv column names.
const std::vector<std::string>& SummaryMetrics();
// summary.csv's columns; track_bands.csv's.
const std::vector<ColumnInfo>& SummaryColumns();
const std::vector<ColumnInfo>& TrackBandColumns();

// Reads `runs_csv` (streamed; memory grows with the number of values, not rows) and returns the
// summary.csv text; false with *why naming the file and record on a malformed file.
bool SummarizeRuns(const std::string& runs_csv, std::string* summary_csv, std::string* why);

// track_bands.csv from track_errors.csv (run_row.h): the per-time Monte Carlo summary of a tracking
// scenario's errors over its trials, one row per (scenario, point, method, t_s, quantity), in the
// order the (scenario, point, method, t_s) first appear; quantity: each tracked quantity, then
// nees and nees_rotation. Columns: n (trials with a finite value), mean, median, median_abs,
// p2_5, p97_5. A missing track_errors.csv gives the header only.
bool SummarizeTrackErrors(const std::string& track_errors_csv, std::string* bands_csv,
                          std::string* why);

}  // namespace calibench
