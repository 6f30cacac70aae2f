// The methods a scenario can run on one trial's measurements, each yielding RunRows:
//   adaptive       the thesis estimator on the source itself (continuous or held frames);
//   dlt            normalised DLT on all frames pooled (non-coplanar points);
//   zhang          cv::calibrateCamera on the (frame, board) views of a board scenario, then the
//                  constant extrinsic from the per-view board poses and the known body poses by
//                  chordal rotation averaging and a mean position;
//   zhang_handeye  the same intrinsics, extrinsic from cv::calibrateHandEye (Tsai) instead;
//   ceres          maximum likelihood over intrinsics and the constant extrinsic, from dlt or
//   zhang.
// Every method sees the same source, hence the same noise draw.
#pragma once

#include <string>
#include <vector>

#include "bench/runner.h"
#include "bench/scenario.h"
#include "core/measurements.h"

namespace calibench {

// Method names (as in the `method` column) the scenario enables, in row order.
std::vector<std::string> EnabledMethods(const ScenarioConfig& s);

// Which of the enabled methods to run (a measurement group copies the others' rows).
struct MethodSelection {
  bool adaptive = true;
  bool batch = true;          // dlt, zhang, zhang_handeye, ceres.
  bool record_curve = false;  // Keep the adaptive run's ||theta~||(t) in RunRow::curve.
  int curve_samples = 300;    // At most this many samples (evenly spaced in recorded time).
};

// `shared` (may be null) holds what every trial of the scenario would compute alike.
std::vector<RunRow> RunMethods(const ScenarioConfig& s, const SceneTruth& scene,
                               const MeasurementSource& source, const RunRow& base,
                               ScenarioShared* shared, const MethodSelection& selection = {});

}  // namespace calibench
