// The rows calibench writes: RunRow (one per scenario, trial and method instance), its runs.csv
// layout and CSV codec, and the columns of timings.csv, curves.csv and the tracking files. The
// layout is the list of columns in run_row.cc, in file order (columns are only ever appended),
// with one slot, after converge_time_s, for the outputs the registered method types declare
// (methods/registry.h DeclaredOutputs, in registry order); the names, units and docs of the
// quantities are the metric table's and the declarations' (RunQuantities; metrics/metric_table.h
// has the naming rule every column follows). Every runs.csv byte is deterministic (no timing).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench/config/scenario.h"
#include "metrics/metric_table.h"
#include "metrics/rig_metrics.h"
#include "metrics/tracking.h"

namespace calibench {

// Rig runs (a scenario with `rig:`): the relative pose of camera c >= 1 against camera 0 as the
// same method estimated both (metrics/rig_metrics.h), one rig.csv line per (scenario, trial,
// method, camera c >= 1). The final estimates against the truth at the end of the run; tracking
// scenarios also the relative rotation and baseline over time, on the segment after the last
// truth change that moves camera 0 or c (from the start when none): re-convergence of the
// relative rotation's geodesic error to tracking.tolerance's 0.1 deg-like `rel_rot_tol_deg`, its
// steady and peak error, the steady |baseline error|.
struct RigRow {
  std::string status;  // ok when both cameras' rows are ok; else the first not-ok one's.
  RigErrors errors;
  double segment_from_s = kUnset;
  double rel_rot_tol_deg = kUnset;
  SegmentFigures rel_rot;       // Of the geodesic error, deg.
  SegmentFigures baseline_mm;   // Of |baseline error|, mm.
  SegmentFigures vdisp_rms_px;  // Of the plane's RMS vertical disparity, px.
};

// One CSV row. Members are named as their runs.csv columns (metrics/metric_table.h has the naming
// rule, the units and a doc of each); err_* are signed (estimate - truth); NaN where a figure does
// not apply or the method failed.
struct RunRow {
  std::string scenario;
  std::string sweep;  // SweepPoint::sweep, index and params.
  int point = 0;
  std::string params;
  int n_points = 0;  // Feature points of the scenario (all boards' corners).
  int trial = 0;
  uint64_t seed = 0;
  std::string method;
  std::string status;  // ok | diverged | failed
  std::string message;
  double fku_px = kUnset, fkv_px = kUnset, phi_deg = kUnset, u0_px = kUnset, v0_px = kUnset;
  double roll_deg = kUnset, pitch_deg = kUnset, yaw_deg = kUnset;  // Of R_C.
  double xc_x_m = kUnset, xc_y_m = kUnset, xc_z_m = kUnset;
  double err_fku_px = kUnset, err_fkv_px = kUnset, err_phi_deg = kUnset, err_u0_px = kUnset,
         err_v0_px = kUnset;
  double rot_err_deg = kUnset, xc_err_m = kUnset;
  double theta_err_norm = kUnset;
  double rms_reproj_px = kUnset;    // Per-point RMS (Euclidean), over all frames.
  double converge_time_s = kUnset;  // NaN: never stayed below the tolerance.
  // The method's declared outputs it set (MethodResult::outputs), by column name; NaN when absent.
  std::map<std::string, double> method_outputs;
  double ortho_defect = kUnset;  // ||R^T R - I||_F of the recovered R before projection.
  // Reported standard deviations (ceres covariance) and the Cramer-Rao bound (sigma^2 (J^T J)^-1
  // at the truth; only with pixel noise alone, which is what it models).
  double std_fku_px = kUnset, std_fkv_px = kUnset, std_phi_deg = kUnset, std_u0_px = kUnset,
         std_v0_px = kUnset;
  double crlb_fku_px = kUnset, crlb_fkv_px = kUnset, crlb_phi_deg = kUnset, crlb_u0_px = kUnset,
         crlb_v0_px = kUnset;
  int improper = 0;  // 1 when the recovered rotation is a reflection.
  long steps = 0;    // Integrator steps / solver iterations.
  // detections: rendered (the same for every method of a trial; NaN / -1 for oracle).
  double detect_rate = kUnset;    // Tags detected / tags fully in the image.
  double corner_rms_px = kUnset;  // Detected corners vs exact projections.
  int frames_no_detection = -1;
  // Per-angle extrinsic errors: roll, pitch, yaw of R_C (README convention), estimate minus truth,
  // wrapped to (-180, 180]. Appended after `message` (the columns before it are unchanged).
  double err_roll_deg = kUnset, err_pitch_deg = kUnset, err_yaw_deg = kUnset;
  // The data the method's estimate used (methods/method.h MethodResult::frames_used): frames with
  // at least one observation and corner observations. Appended after err_yaw_deg.
  long n_frames_used = -1, n_obs_used = -1;
  // detections: rendered: the mean corner error along the tags' diagonals, outward (> 0: tags
  // look larger; detect/rendered_source.h). NaN for oracle. Appended after n_obs_used.
  double corner_radial_bias_px = kUnset;
  // detections: rendered: the RMS of the corners' Cramer-Rao std per axis (the photometric fit's,
  // Observation::crlb_px): the floor corner_rms_px / sqrt(2) is measured against. NaN for oracle
  // and for refinements that report none. Appended after corner_radial_bias_px.
  double corner_crlb_px = kUnset;
  // The estimate's projection error against the truth over the image and its ratio to the
  // projection std its own covariance predicts (metrics/metrics.h ProjectionErrorAgainst; NaN:
  // no camera, or no covariance for the ratio). Appended after corner_crlb_px.
  double proj_err_px = kUnset, proj_err_ratio = kUnset;
  // Rig runs: the row's camera (its index in rig.cameras; 0 for a scenario without rig). Written
  // (the `camera` column of runs.csv and of the other per-row files) only in rig runs.
  int camera = 0;
  // Rig runs, camera c >= 1: its relative pose against camera 0 by the same method (rig.csv).
  std::optional<RigRow> rig;
  // Not written: the estimate's parent_from_cam (a proper one), and its trajectory at the report
  // times of a tracking scenario (nullopt before the first estimate): the rig metrics' inputs.
  std::optional<Rigid3> est_parent_from_cam;
  std::vector<std::optional<Rigid3>> pose_track;
  // Not in runs.csv (they vary from run to run): timings.csv and curves.csv.
  double wall_ms = kUnset;     // The method's own wall time; 0 when copied (reused).
  double measure_ms = kUnset;  // Producing the group's measurements (render + detect).
  bool reused = false;         // Copied from an earlier point of the group with equal settings.
  int frames = 0;              // Frames of the trial's source (timings.csv: cost per frame).
  // ||theta~||(t) of a method that reports estimates over time, when recorded (trial.h).
  std::vector<std::pair<double, double>> curve;
  // When the scenario tracks (ScenarioConfig::Tracks) and the method reported estimates over
  // time: its trajectory at the report times, and the per-event figures (metrics/tracking.h).
  std::vector<TrackPoint> track;
  std::vector<EventMetrics> events;
};

// A column of a file: its name, unit ("" when dimensionless) and a one-line doc (schema.json).
struct ColumnInfo {
  std::string name, unit, doc;
};

// Every quantity of a run: the metric table with the registered types' declared outputs
// (id Metric::kMethodOutput, value column only) after kMethodOutputsAfter. The order of
// summary.csv's metrics and of schema.json's quantities.
const std::vector<MetricSpec>& RunQuantities();

// runs.csv: header and fields; ParseRunRow is the inverse (false naming the bad column).
const std::vector<std::string>& RunRowHeader();
const std::vector<ColumnInfo>& RunRowColumns();
std::vector<std::string> RunRowFields(const RunRow& row, bool camera_column = false);
bool ParseRunRow(const std::vector<std::string>& header, const std::vector<std::string>& fields,
                 RunRow* row, std::string* why);
// timings.csv (scenario, trial, method, wall_ms, measure_ms, reused, wall_per_frame_us: the
// method's wall time per frame of the trial) and curves.csv (scenario, trial, method, t_s,
// theta_err_norm).
const std::vector<std::string>& TimingHeader();
std::vector<std::string> TimingFields(const RunRow& row, bool camera_column = false);
const std::vector<std::string>& CurveHeader();
const std::vector<ColumnInfo>& TimingColumns();
const std::vector<ColumnInfo>& CurveColumns();

// The tracking files (a scenario whose truth changes; run_dir.h):
//   events.csv        one line per (row, event, quantity): scenario, point, trial, method, event,
//                     quantity, at_s, tol, reconverge_s, steady_err, peak_err (in the
//                     quantity's unit: metric_table.h, rule 4);
//   tracks.csv        trial 0's trajectories: scenario, point, trial, method, t_s, then per
//                     quantity est_Q and true_Q, then nees, nees_rotation;
//   track_errors.csv  every trial's errors at the band times (at most band_samples per trial):
//                     scenario, point, trial, method, t_s, err_Q per quantity, nees,
//                     nees_rotation.
const std::vector<std::string>& EventHeader();
const std::vector<std::string>& TrackHeader();
const std::vector<std::string>& TrackErrorHeader();
const std::vector<ColumnInfo>& EventColumns();
const std::vector<ColumnInfo>& TrackColumns();
const std::vector<ColumnInfo>& TrackErrorColumns();
std::string EventLines(const RunRow& row, bool camera_column = false);
std::string TrackLines(const RunRow& row, bool camera_column = false);
// `band_samples`: the most report times per trial (evenly thinned, always keeping the last).
std::string TrackErrorLines(const RunRow& row, int band_samples, bool camera_column = false);

// Rig runs (RunConfig::HasRig): every per-row file (runs, timings, curves, events, tracks,
// track_errors; their *Fields / *Lines with camera_column) ends in a `camera` column
// (CameraColumn), and summary.csv and track_bands.csv are per camera too; a run without a rig has
// none of it. rig.csv (RigColumns): one line per (scenario, trial, method, camera c >= 1), RigRow.
ColumnInfo CameraColumn();
std::vector<ColumnInfo> WithCameraColumn(std::vector<ColumnInfo> columns, bool camera_column);
std::vector<std::string> WithCameraColumn(std::vector<std::string> header, bool camera_column);
const std::vector<ColumnInfo>& RigColumns();
const std::vector<std::string>& RigHeader();
std::string RigLines(const RunRow& row);  // Empty unless row.rig.

}  // namespace calibench
