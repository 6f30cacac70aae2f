// The metric table: every quantity the harness computes and writes to a CSV file, declared once
// (MetricTable()), with its name, unit, label, a one-line doc, the columns it has, how summary.csv
// summarises it, its companion columns and whether the tracking files carry it. The figures a
// method reports of itself are declared by its type instead (methods/method.h OutputSpec) and
// join the table at kMethodOutputsAfter (bench/run/run_row.h RunQuantities). The row writer
// (bench/run/run_row.cc), the summary writer (bench/run/summary.cc), the track writers
// (run_row.cc, through TrackQuantityNames in tracking.h) and schema.json (bench/run/schema.h) are
// made from both; the report reads schema.json, never its own list of quantities.
//
// The naming rule of every column of every CSV file of a run directory (runs.csv, summary.csv,
// timings.csv, curves.csv, events.csv, tracks.csv, track_errors.csv, track_bands.csv):
//   1. Lower-case words joined by '_'. A column holding a dimensional number ends in its unit:
//      _px, _deg, _m, _s, _ms, _us (fku_px, phi_deg, xc_x_m, converge_time_s, wall_ms,
//      wall_per_frame_us). A dimensionless one (a count, a flag, a ratio, an index, ||theta~||,
//      NEES) has no unit (n_obs_used, improper, detect_rate, theta_err_norm, nees). The rig
//      figures (rig.csv, bench/run/run_row.h RigColumns) also use _mm and _pct (percent of the
//      true value: err_baseline_mm, depth_err_10m_pct).
//   2. A quantity Q is named with its unit (fku_px, pitch_deg) and its columns by prefix:
//        Q        the estimate                                   runs.csv
//        err_Q    estimate minus truth, signed                   runs.csv, track_errors.csv
//        std_Q    the standard deviation the method reports      runs.csv
//        crlb_Q   the Cramer-Rao standard deviation              runs.csv
//        est_Q, true_Q   estimate and truth over time            tracks.csv
//   3. A figure that is not a parameter is one column, unit last: an error magnitude
//      (rot_err_deg: the geodesic angle; xc_err_m: |x_C estimate - x_C|), a fit (rms_reproj_px),
//      a time (converge_time_s), a detection figure (corner_rms_px).
//   4. A long table, one row per quantity, names it in a `metric` (summary.csv) or `quantity`
//      (events.csv, track_bands.csv) column by its column name, unit included (err_fku_px,
//      pitch_deg); its value columns (median, rmse, tol, steady_err, ...) are in that unit.
#pragma once

#include <string>
#include <vector>

namespace calibench {

// Every quantity of the table, in its order (with the method outputs after kMethodOutputsAfter:
// the order of summary.csv's metrics and of the report's quantities). runs.csv's column order is
// its own (run_row.cc): columns are only ever appended there, but for the method outputs' slot.
enum class Metric {
  kFku,
  kFkv,
  kU0,
  kV0,
  kPhi,
  kRoll,
  kPitch,
  kYaw,
  kRotErr,
  kXcX,
  kXcY,
  kXcZ,
  kXcErr,
  kRmsReproj,
  kThetaErr,
  kConvergeTime,
  kOrthoDefect,
  kImproper,
  kSteps,
  kFramesUsed,
  kObsUsed,
  kDetectRate,
  kCornerRms,
  kCornerRadialBias,
  kCornerCrlb,
  kFramesNoDetection,
  kProjErr,
  kProjErrRatio,
  // Not in the table: the id of a quantity a method type declares (methods/method.h OutputSpec).
  kMethodOutput,
};

// The method types' declared outputs follow this quantity in the quantities of a run and its
// column in runs.csv (bench/run/run_row.h).
inline constexpr Metric kMethodOutputsAfter = Metric::kConvergeTime;

// The columns a quantity has (rule 2); bits of MetricSpec::columns.
enum MetricColumn : unsigned {
  kValueColumn = 1u << 0,  // Q: the estimate, or the figure itself.
  kErrorColumn = 1u << 1,  // err_Q.
  kStdColumn = 1u << 2,    // std_Q.
  kCrlbColumn = 1u << 3,   // crlb_Q.
};

// How summary.csv summarises a quantity (its error column if it has one, else its value) over the
// ok rows of a (scenario, method): n_used, median, mean, std, p2_5, p97_5 of the signed values and
// median_abs, p2_5_abs, p97_5_abs of |value|; kWithRmse adds the RMSE (the truth is the
// reference). With a crlb_Q / std_Q companion, also the median bound (crlb, rmse_over_crlb) and
// the median reported std (std_reported).
enum class Summary { kNone, kStatistics, kWithRmse };

struct MetricSpec {
  Metric id;
  const char* name;   // Q, unit included: its value column's name.
  const char* unit;   // "px", "deg", "m", "s"; "" when dimensionless.
  const char* label;  // Short, for tables and plots ("f·ku").
  const char* doc;    // One line.
  unsigned columns = kValueColumn;
  bool integer = false;  // runs.csv writes it as an integer (counts, flags; -1: not recorded).
  // Its index in the tracked quantities (tracking.h TrackValues: tracks.csv, track_errors.csv,
  // events.csv, the tracking tolerances); -1 when not tracked.
  int track = -1;
  Summary summary = Summary::kNone;
  // The report ranks methods on it (smaller |value| is better) and compares them pairwise.
  bool ranked = false;
  // Bound on the 97.5th percentile of |error| (0.1 deg on roll, pitch: Algers 2018, §1.2); 0: none.
  double target = 0.0;
  // The report's first page answers each question on it (f*ku for the intrinsics, the geodesic
  // angle for the extrinsic rotation).
  bool headline = false;
  // The report's section on where each method's image projects right (proj_err_px: "error",
  // proj_err_ratio: "ratio"); nullptr for the others.
  const char* projection = nullptr;
};

// The table, in Metric order.
const std::vector<MetricSpec>& MetricTable();
const MetricSpec& Spec(Metric metric);
// A column of a quantity by rule 2: "fku_px", "err_fku_px", "std_fku_px", "crlb_fku_px".
std::string ColumnName(const MetricSpec& spec, MetricColumn column);
std::string ColumnName(Metric metric, MetricColumn column);
// The column summary.csv summarises (its `metric` value): err_Q if the quantity has one, else Q.
std::string SummaryColumn(const MetricSpec& spec);
// A one-line doc of a derived column (err_Q, std_Q, crlb_Q).
std::string ColumnDoc(const MetricSpec& spec, MetricColumn column);

}  // namespace calibench
