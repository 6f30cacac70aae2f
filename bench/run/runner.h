// Runs scenarios as tasks: a task is one trial of one measurement group (trial.h: the group's
// measurements once, then every enabled method instance of every scenario of the group). A group
// is one scenario, or the consecutive points of a sweep that differ only in methods' options
// (SweepPoint::measurement_index). Tasks run in parallel; rows come back in (group, trial,
// scenario, instance) order whatever the thread count, and every number in runs.csv is
// independent of it (timings go to timings.csv).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bench/config/scenario.h"
#include "bench/run/run_row.h"
#include "bench/run/trial.h"

namespace calibench {

// The measurement groups of `scenarios`: runs of consecutive indices sharing measurements.
std::vector<std::vector<int>> MeasurementGroups(const std::vector<ScenarioConfig>& scenarios);

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
  // Called each time a task's rows are handed over, in task order, with (tasks handed over so far,
  // total tasks); from the worker threads, serialised.
  std::function<void(int done, int total)> progress;
};

std::vector<RunRow> RunScenarios(const std::vector<ScenarioConfig>& scenarios,
                                 const RunOptions& options);

}  // namespace calibench
