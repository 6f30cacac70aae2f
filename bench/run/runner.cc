#include "bench/run/runner.h"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <type_traits>

#include "util/parallel_for.h"

namespace calibench {

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
  const int threads = ParallelWorkers(options.threads, tasks.size());
  // Tasks start in order; task k waits until fewer than `window` tasks before it are still
  // uncommitted (memory stays bounded), and rows are committed in task order.
  const size_t window = options.max_buffered_tasks > 0
                            ? static_cast<size_t>(options.max_buffered_tasks)
                            : 4 * static_cast<size_t>(threads);
  std::vector<ScenarioShared> shared(scenarios.size());
  std::mutex mutex;
  std::condition_variable cv;
  size_t next_commit = 0;
  std::map<size_t, std::vector<RunRow>> ready;
  bool stop = false;
  ParallelForOptions parallel;
  parallel.threads = threads;
  parallel.spawn_every_worker = true;  // As zhang's reproducibility needs (docs/reliability.md).
  ParallelFor(tasks.size(), parallel, [&](int /*worker*/, size_t k) {
    {
      std::unique_lock<std::mutex> lock(mutex);
      cv.wait(lock, [&] { return stop || k < next_commit + window; });
      if (stop) return;
    }
    const TrialTask& task = tasks[k];
    const std::vector<int>& group = groups[task.group];
    std::vector<const ScenarioConfig*> members;
    members.reserve(group.size());
    for (int i : group) members.push_back(&scenarios[i]);
    GroupTrialOptions trial_options;
    trial_options.record_curve = task.trial < options.curve_trials;
    std::vector<RunRow> rows = RunGroupTrial(members, task.trial, &shared[group[0]], trial_options);
    std::lock_guard<std::mutex> lock(mutex);
    ready.emplace(k, std::move(rows));
    while (!stop && !ready.empty() && ready.begin()->first == next_commit) {
      stop = !commit(next_commit, std::move(ready.begin()->second));
      ready.erase(ready.begin());
      ++next_commit;
    }
    cv.notify_all();
  });
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
