// Runs scenarios: every (measurement group, trial) builds its measurement source once from
// ScenarioConfig::TrialSeedOf(trial), runs every enabled method of every scenario of the group on
// it, and yields one RunRow per (scenario, method). A group is one scenario, or the consecutive
// points of a sweep that differ only in methods' settings (SweepPoint::measurement_index); inside
// it a method whose settings equal an earlier point's is not run again: its rows are copied.
// Trials run in parallel; rows come back in (group, trial, scenario, method) order whatever the
// thread count, and every number in runs.csv is independent of it (timings go to timings.csv).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "bench/scenario.h"

namespace calibench {

// One CSV row. Angles in degrees, pixels in px, lengths in the scene's unit (m). err_* are signed
// (estimate - truth); NaN where a figure does not apply or the method failed.
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
  double fku = kUnset, fkv = kUnset, phi_deg = kUnset, u0 = kUnset, v0 = kUnset;
  double rc_roll_deg = kUnset, rc_pitch_deg = kUnset, rc_yaw_deg = kUnset;
  double xc_x = kUnset, xc_y = kUnset, xc_z = kUnset;
  double err_fku = kUnset, err_fkv = kUnset, err_phi_deg = kUnset, err_u0 = kUnset, err_v0 = kUnset;
  double rot_err_deg = kUnset, err_xc_norm = kUnset;
  double theta_err_norm = kUnset;
  double rms_reproj_px = kUnset;    // Per-point RMS (Euclidean), over all frames.
  double converge_time_s = kUnset;  // NaN: never stayed below the tolerance.
  double pe_min_eig = kUnset;       // PersistentExcitationIndex (adaptive only).
  double ortho_defect = kUnset;     // ||R^T R - I||_F of the recovered R before projection.
  // Reported standard deviations (ceres covariance) and the Cramer-Rao bound (sigma^2 (J^T J)^-1
  // at the truth; only with pixel noise alone, which is what it models).
  double std_fku = kUnset, std_fkv = kUnset, std_phi_deg = kUnset, std_u0 = kUnset, std_v0 = kUnset;
  double crlb_fku = kUnset, crlb_fkv = kUnset, crlb_phi_deg = kUnset, crlb_u0 = kUnset,
         crlb_v0 = kUnset;
  int improper = 0;  // 1 when the recovered rotation is a reflection.
  long steps = 0;    // Integrator steps / solver iterations.
  // detections: rendered (the same for every method of a trial; NaN / -1 for oracle).
  double detect_rate = kUnset;    // Tags detected / tags fully in the image.
  double corner_rms_px = kUnset;  // Detected corners vs exact projections.
  int frames_no_detection = -1;
  // Not in runs.csv (they vary from run to run): timings.csv and curves.csv.
  double wall_ms = kUnset;     // The method's own wall time; 0 when copied (reused).
  double measure_ms = kUnset;  // Producing the group's measurements (render + detect).
  bool reused = false;         // Copied from an earlier point of the group with equal settings.
  // ||theta~||(t) of the adaptive run, when recorded (RunGroupTrial's record_curve).
  std::vector<std::pair<double, double>> curve;
};

// runs.csv: header and fields; ParseRunRow is the inverse (false naming the bad column).
const std::vector<std::string>& RunRowHeader();
std::vector<std::string> RunRowFields(const RunRow& row);
bool ParseRunRow(const std::vector<std::string>& header, const std::vector<std::string>& fields,
                 RunRow* row, std::string* why);
// timings.csv (scenario, trial, method, wall_ms, measure_ms, reused) and curves.csv (scenario,
// trial, method, t_s, theta_err_norm).
const std::vector<std::string>& TimingHeader();
std::vector<std::string> TimingFields(const RunRow& row);
const std::vector<std::string>& CurveHeader();

// Results the trials of one scenario share, computed once by whichever trial needs them first.
// They depend on the scenario alone, so their values do not depend on which trial or thread
// computes them (the rows stay identical for any thread count).
struct ScenarioShared {
  std::once_flag crlb_once;
  bool crlb_valid = false;
  std::array<double, 5> crlb_std{};  // fku, fkv, phi_deg (NaN without skew), u0, v0.
};

// Runs one trial of one scenario; never throws for bad data (a failed row instead). `shared`
// (optional) lets the scenario's trials share per-scenario work.
std::vector<RunRow> RunTrial(const ScenarioConfig& scenario, int trial,
                             ScenarioShared* shared = nullptr);

// The measurement groups of `scenarios`: runs of consecutive indices sharing measurements.
std::vector<std::vector<int>> MeasurementGroups(const std::vector<ScenarioConfig>& scenarios);

struct GroupTrialOptions {
  bool record_curve = false;  // Keep the adaptive runs' ||theta~||(t) (RunRow::curve).
  int curve_samples = 300;    // At most this many (t, ||theta~||) pairs per run.
};
// One trial of one measurement group: the measurements once, then every scenario's methods.
// `shared[j]` (optional) belongs to group[j].
std::vector<RunRow> RunGroupTrial(const std::vector<const ScenarioConfig*>& group, int trial,
                                  ScenarioShared* shared, const GroupTrialOptions& options);

// One unit of work: a trial of a measurement group; `index` numbers a config's tasks in order.
struct TrialTask {
  int group = 0;
  int trial = 0;
  long index = 0;
};
// Every task of `scenarios` (grouped by MeasurementGroups), in order.
std::vector<TrialTask> ListTasks(const std::vector<ScenarioConfig>& scenarios,
                                 const std::vector<std::vector<int>>& groups);

struct TaskRunOptions {
  int threads = 0;              // 0: all cores.
  long max_buffered_tasks = 0;  // Finished tasks waiting for an earlier one; 0: 4 x threads.
  int curve_trials = 0;         // Record ||theta~||(t) for trials below this.
};
// Runs `tasks` in parallel and hands each task's rows to `commit(position, rows)` in list order,
// serialised. When commit returns false no further task starts. Tasks run on spawned threads only:
// OpenCV's calibrateCamera gives results that differ in the last digits between the main thread
// and spawned ones.
void RunTasksInOrder(
    const std::vector<ScenarioConfig>& scenarios, const std::vector<std::vector<int>>& groups,
    const std::vector<TrialTask>& tasks, const TaskRunOptions& options,
    const std::function<bool(size_t position, std::vector<RunRow>&& rows)>& commit);

struct RunOptions {
  int threads = 0;  // 0: all cores.
  // Called after each finished trial with (done, total); from the worker threads, serialised.
  std::function<void(int done, int total)> progress;
};

std::vector<RunRow> RunScenarios(const std::vector<ScenarioConfig>& scenarios,
                                 const RunOptions& options);

}  // namespace calibench
