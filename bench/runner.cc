#include "bench/runner.h"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

#include "batch/zhang.h"
#include "bench/csv.h"
#include "bench/methods.h"
#include "core/random.h"

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
  static const std::vector<std::string> header = {"scenario", "trial",      "method",
                                                  "wall_ms",  "measure_ms", "reused"};
  return header;
}

std::vector<std::string> TimingFields(const RunRow& r) {
  return {r.scenario,
          std::to_string(r.trial),
          r.method,
          FormatNumber(r.wall_ms),
          FormatNumber(r.measure_ms),
          r.reused ? "1" : "0"};
}

const std::vector<std::string>& CurveHeader() {
  static const std::vector<std::string> header = {"scenario", "trial", "method", "t_s",
                                                  "theta_err_norm"};
  return header;
}

namespace {

// The trial's measurement source; *base gets the seed and the detection figures. Null (and *why)
// when the measurements cannot be produced.
std::unique_ptr<MeasurementSource> MakeSource(const ScenarioConfig& s, const SceneTruth& scene,
                                              RunRow* base, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<MeasurementSource> source;
  if (s.detections == "rendered") {
    auto rendered =
        RenderedSource::Create(scene, s.aprilgrids, s.RenderingOptions(), base->seed, why);
    if (rendered) {
      const DetectionStats& stats = rendered->stats();
      base->detect_rate = stats.DetectionRate();
      base->corner_rms_px = stats.rms_px;
      base->frames_no_detection = stats.frames_without_detections;
    }
    source = std::move(rendered);
  } else {
    source = OracleSource::Create(scene, s.OracleSourceOptions(), base->seed, why);
  }
  base->measure_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return source;
}

RunRow BaseRow(const ScenarioConfig& s, int trial) {
  RunRow base;
  base.scenario = s.name;
  base.sweep = s.sweep_point.sweep.empty() ? s.name : s.sweep_point.sweep;
  base.point = s.sweep_point.index;
  base.params = s.sweep_point.params;
  base.n_points = static_cast<int>(s.points.size());
  base.trial = trial;
  base.seed = s.TrialSeedOf(trial);
  return base;
}

// Rows `from` relabelled as scenario `s`'s (copied, not run again).
void AppendCopies(const std::vector<RunRow>& from, const RunRow& base, std::vector<RunRow>* rows) {
  for (RunRow row : from) {
    row.scenario = base.scenario;
    row.sweep = base.sweep;
    row.point = base.point;
    row.params = base.params;
    row.n_points = base.n_points;
    row.wall_ms = 0.0;
    row.measure_ms = base.measure_ms;
    row.reused = true;
    rows->push_back(std::move(row));
  }
}

}  // namespace

std::vector<RunRow> RunTrial(const ScenarioConfig& s, int trial, ScenarioShared* shared) {
  return RunGroupTrial({&s}, trial, shared, GroupTrialOptions());
}

std::vector<std::vector<int>> MeasurementGroups(const std::vector<ScenarioConfig>& scenarios) {
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < scenarios.size(); ++i) {
    const SweepPoint& p = scenarios[i].sweep_point;
    if (i > 0 && p.measurement_index >= 0) {
      const SweepPoint& q = scenarios[i - 1].sweep_point;
      if (q.sweep == p.sweep && q.measurement_index == p.measurement_index) {
        groups.back().push_back(static_cast<int>(i));
        continue;
      }
    }
    groups.push_back({static_cast<int>(i)});
  }
  return groups;
}

namespace {

std::vector<RunRow> RunGroupTrialUnguarded(const std::vector<const ScenarioConfig*>& group,
                                           int trial, ScenarioShared* shared,
                                           const GroupTrialOptions& options) {
  const ScenarioConfig& first = *group.front();
  RunRow base = BaseRow(first, trial);
  std::string why;
  const SceneTruth scene = first.MakeScene();
  const std::unique_ptr<MeasurementSource> source = MakeSource(first, scene, &base, &why);
  std::vector<RunRow> rows;
  // Per scenario of the group: its adaptive rows and its batch rows, for copying.
  std::vector<std::vector<RunRow>> adaptive_rows(group.size()), batch_rows(group.size());
  for (size_t j = 0; j < group.size(); ++j) {
    const ScenarioConfig& s = *group[j];
    RunRow row_base = BaseRow(s, trial);
    row_base.detect_rate = base.detect_rate;
    row_base.corner_rms_px = base.corner_rms_px;
    row_base.frames_no_detection = base.frames_no_detection;
    row_base.measure_ms = j == 0 ? base.measure_ms : 0.0;
    if (!source) {
      for (const std::string& method : EnabledMethods(s)) {
        RunRow failed = row_base;
        failed.method = method;
        failed.status = "failed";
        failed.message = "measurements: " + why;
        rows.push_back(failed);
      }
      continue;
    }
    // An earlier scenario of the group whose settings for these methods are the same.
    auto same_as = [&](auto key) -> int {
      for (size_t k = 0; k < j; ++k) {
        if (key(*group[k]) == key(s)) return static_cast<int>(k);
      }
      return -1;
    };
    const int adaptive_from =
        same_as([](const ScenarioConfig& c) { return c.sweep_point.adaptive_key; });
    const int batch_from = same_as([](const ScenarioConfig& c) { return c.sweep_point.batch_key; });
    MethodSelection selection;
    selection.adaptive = adaptive_from < 0;
    selection.batch = batch_from < 0;
    selection.record_curve = options.record_curve;
    selection.curve_samples = options.curve_samples;
    std::vector<RunRow> run =
        RunMethods(s, scene, *source, row_base, shared ? shared + j : nullptr, selection);
    for (RunRow& r : run) (r.method == "adaptive" ? adaptive_rows[j] : batch_rows[j]).push_back(r);
    if (adaptive_from >= 0) AppendCopies(adaptive_rows[adaptive_from], row_base, &adaptive_rows[j]);
    if (batch_from >= 0) AppendCopies(batch_rows[batch_from], row_base, &batch_rows[j]);
    rows.insert(rows.end(), adaptive_rows[j].begin(), adaptive_rows[j].end());
    rows.insert(rows.end(), batch_rows[j].begin(), batch_rows[j].end());
  }
  return rows;
}

}  // namespace

std::vector<RunRow> RunGroupTrial(const std::vector<const ScenarioConfig*>& group, int trial,
                                  ScenarioShared* shared, const GroupTrialOptions& options) {
  std::string error;
  try {
    return RunGroupTrialUnguarded(group, trial, shared, options);
  } catch (const std::exception& e) {  // e.g. std::bad_alloc: this trial fails, the sweep goes on.
    error = std::string("internal error: ") + e.what();
  }
  std::vector<RunRow> rows;
  for (const ScenarioConfig* s : group) {
    for (const std::string& method : EnabledMethods(*s)) {
      RunRow failed = BaseRow(*s, trial);
      failed.method = method;
      failed.status = "failed";
      failed.message = error;
      rows.push_back(failed);
    }
  }
  return rows;
}

std::vector<TrialTask> ListTasks(const std::vector<ScenarioConfig>& scenarios,
                                 const std::vector<std::vector<int>>& groups) {
  std::vector<TrialTask> tasks;
  for (size_t g = 0; g < groups.size(); ++g) {
    for (int t = 0; t < scenarios[groups[g][0]].trials; ++t) {
      tasks.push_back({static_cast<int>(g), t, static_cast<long>(tasks.size())});
    }
  }
  return tasks;
}

void RunTasksInOrder(
    const std::vector<ScenarioConfig>& scenarios, const std::vector<std::vector<int>>& groups,
    const std::vector<TrialTask>& tasks, const TaskRunOptions& options,
    const std::function<bool(size_t position, std::vector<RunRow>&& rows)>& commit) {
  if (tasks.empty()) return;
  int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::max(1, std::min<int>(threads, static_cast<int>(tasks.size())));
  const size_t window = options.max_buffered_tasks > 0
                            ? static_cast<size_t>(options.max_buffered_tasks)
                            : 4 * static_cast<size_t>(threads);
  std::vector<ScenarioShared> shared(scenarios.size());
  std::mutex mutex;
  std::condition_variable cv;
  size_t next_task = 0, next_commit = 0;
  std::map<size_t, std::vector<RunRow>> ready;
  bool stop = false;
  auto worker = [&] {
    while (true) {
      size_t k;
      {
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait(lock, [&] {
          return stop || next_task >= tasks.size() || next_task < next_commit + window;
        });
        if (stop || next_task >= tasks.size()) return;
        k = next_task++;
      }
      const TrialTask& task = tasks[k];
      const std::vector<int>& group = groups[task.group];
      std::vector<const ScenarioConfig*> members;
      members.reserve(group.size());
      for (int i : group) members.push_back(&scenarios[i]);
      GroupTrialOptions trial_options;
      trial_options.record_curve = task.trial < options.curve_trials;
      std::vector<RunRow> rows =
          RunGroupTrial(members, task.trial, &shared[group[0]], trial_options);
      std::lock_guard<std::mutex> lock(mutex);
      ready.emplace(k, std::move(rows));
      while (!stop && !ready.empty() && ready.begin()->first == next_commit) {
        stop = !commit(next_commit, std::move(ready.begin()->second));
        ready.erase(ready.begin());
        ++next_commit;
      }
      cv.notify_all();
    }
  };
  UseSequentialOpenCv();  // Before the workers start.
  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
}

std::vector<RunRow> RunScenarios(const std::vector<ScenarioConfig>& scenarios,
                                 const RunOptions& options) {
  const std::vector<std::vector<int>> groups = MeasurementGroups(scenarios);
  const std::vector<TrialTask> tasks = ListTasks(scenarios, groups);
  TaskRunOptions run_options;
  run_options.threads = options.threads;
  std::vector<RunRow> rows;
  RunTasksInOrder(
      scenarios, groups, tasks, run_options, [&](size_t position, std::vector<RunRow>&& task_rows) {
        for (RunRow& row : task_rows) rows.push_back(std::move(row));
        if (options.progress) {
          options.progress(static_cast<int>(position + 1), static_cast<int>(tasks.size()));
        }
        return true;
      });
  return rows;
}

}  // namespace calibench
