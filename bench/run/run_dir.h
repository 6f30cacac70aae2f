// The output directory of `calibench run`: how a sweep is streamed into it, resumed after an
// interruption (kill -9 included), sharded over machines and merged back.
//
// A run is a list of tasks, one per (measurement group, trial) in config order (runner.h); task i
// of a run sharded N ways belongs to shard (i mod N) + 1. Files of a finished DIR:
//   config.resolved.yaml   the configuration, every default filled in (checked on --resume/merge);
//   runs.csv               one row per (scenario, trial, method); every byte deterministic;
//   timings.csv            wall_ms and measure_ms of each row (they vary from run to run);
//   curves.csv             ||theta~||(t) of the adaptive runs of the first trials;
//   tasks.idx              "# calibench tasks: shard K/N of T", then per finished task
//                          "TASK RUNS_END TIMINGS_END CURVES_END" (byte offsets; TASK -1: headers);
//   events.csv, tracks.csv, track_errors.csv, track_bands.csv   tracking (run_row.h, summary.h);
//   summary.csv            summary.h, computed from runs.csv;
//   table.md               the thesis table of the scenarios that are not sweep points;
//   schema.json            what every file's columns hold and each sweep's role (schema.h).
// While running, the first four are appended to in DIR/run.partial/, a task's blocks first and its
// tasks.idx line last, each flushed to the kernel: after a kill, the last complete tasks.idx line
// says which bytes are whole, and --resume truncates the rest and continues from the next task.
// At the end the files move into DIR by rename (tasks.idx last), so DIR never shows a half file.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bench/config/config_io.h"

namespace calibench {

struct ShardSpec {
  int index = 1;  // K in 1..N.
  int count = 1;  // N.
  // "K/N"; false with *why otherwise.
  bool Parse(const std::string& text, std::string* why);
  bool Owns(long task) const { return task % count == index - 1; }
  std::string ToString() const { return std::to_string(index) + "/" + std::to_string(count); }
};

struct RunDirOptions {
  std::string out_dir;
  int threads = 0;      // 0: all cores. The files do not depend on it.
  bool resume = false;  // Continue DIR/run.partial instead of starting over.
  ShardSpec shard;
  int curve_trials = 1;        // Record ||theta~||(t) for trials below this (curves.csv).
  int max_buffered_tasks = 0;  // Finished tasks waiting for an earlier one; 0: 4 x threads.
  std::function<void(long done, long total)> progress;  // Serialised; done counts resumed tasks.
  // Asked after each task is written (serialised): true stops the run there, as an interruption
  // would, leaving run.partial resumable (the CLI's SIGINT / SIGTERM handler).
  std::function<bool()> should_stop;
};

struct RunDirSummary {
  bool ok = false;
  std::string message;     // Why not ok (file, reason), or a note ("already complete").
  long tasks_total = 0;    // Tasks of this shard.
  long tasks_resumed = 0;  // Found complete in run.partial.
  long tasks_run = 0;
  long rows_written = 0;  // By this invocation.
  double wall_s = 0.0;
};

RunDirSummary RunToDirectory(const RunConfig& config, const RunDirOptions& options);

// Combines the finished shard directories 1/N..N/N of one configuration into `out_dir`, whose
// files then equal, byte for byte, those of an unsharded run (timings.csv aside).
bool MergeRunDirectories(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                         std::string* why);

}  // namespace calibench
