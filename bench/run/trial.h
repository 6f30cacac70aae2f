// One trial of a measurement group: its measurements are produced once (from the seed of
// ScenarioConfig::TrialSeedOf(trial)), then every enabled method instance of every scenario of the
// group runs on them, and the metrics (metrics/metrics.h) turn each result into a RunRow.
//
// A group is one scenario, or the consecutive points of a sweep that differ only in methods'
// options (runner.h). Inside a trial each instance's result is computed once per key: its type,
// options, convergence_tol and the keys of the instances it starts from (Method::Prerequisites).
// So a ceres from dlt and the dlt row share one DLT, and a sweep point whose instance has the same
// name and key as an earlier point's copies that row instead of running it (reused = 1 in
// timings.csv). A trial never throws for bad data: its rows say `failed` with the reason.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "bench/config/scenario.h"
#include "bench/run/run_row.h"
#include "metrics/metrics.h"

namespace calibench {

// Results the trials of one scenario share, computed once by whichever trial needs them first.
// They depend on the scenario alone, so their values do not depend on which trial or thread
// computes them (the rows stay identical for any thread count).
struct ScenarioShared {
  std::mutex mutex;
  std::map<std::string, CrlbStd> crlb;  // By parametrisation.
};

struct GroupTrialOptions {
  bool record_curve = false;  // Keep ||theta~||(t) of methods that report it (RunRow::curve).
  int curve_samples = 300;    // At most this many (t, ||theta~||) pairs per row.
};

// One trial of one measurement group; `shared[j]` (optional) belongs to group[j]. Rows come in
// (scenario, instance) order.
std::vector<RunRow> RunGroupTrial(const std::vector<const ScenarioConfig*>& group, int trial,
                                  ScenarioShared* shared, const GroupTrialOptions& options);

// One trial of one scenario.
std::vector<RunRow> RunTrial(const ScenarioConfig& scenario, int trial,
                             ScenarioShared* shared = nullptr);

// The key deciding whether two instances compute the same result on the same measurements.
std::string InstanceKey(const ScenarioConfig& scenario, const MethodInstance& instance);

}  // namespace calibench
