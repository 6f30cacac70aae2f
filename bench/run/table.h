// The thesis comparison table: per scenario, the result of the instance its reference describes
// (Monte Carlo: median and 95% interval) beside the reference, and the worst relative deviation
// from it.
#pragma once

#include <string>
#include <vector>

#include "bench/config/scenario.h"
#include "bench/run/run_row.h"

namespace calibench {

struct ReferenceCheck {
  bool has_reference = false;
  // Single run: the largest |ours - ref| / |ref| over the reference's figures (x_C per component).
  double worst_relative_deviation = 0.0;
  std::string worst_field;
  // theta_err_below references ("exact"): whether ||theta~|| is below it.
  bool exact_expected = false;
  bool exact_met = false;
  // Monte Carlo: how many reference figures lie inside our 95% interval.
  int inside_interval = 0;
  int figures = 0;
};

// The instance whose rows a scenario's reference describes: reference.method, else the scenario's
// first enabled instance.
std::string ReferenceMethod(const ScenarioConfig& scenario);

// Compares the reference method's rows of one scenario with its reference.
ReferenceCheck CheckAgainstReference(const ScenarioConfig& scenario,
                                     const std::vector<RunRow>& rows);

// Markdown table of all scenarios (each with its ReferenceMethod's rows).
std::string ThesisTable(const std::vector<ScenarioConfig>& scenarios,
                        const std::vector<RunRow>& rows);

}  // namespace calibench
