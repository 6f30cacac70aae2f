// The target calibrate --images finds in images: a Kalibr AprilGrid or a checkerboard (read from
// and written as Kalibr's target YAML by io/target_io.h).
#pragma once

#include <string>

#include "sim/target.h"

namespace calibench {

struct CalibrationTarget {
  enum class Type { kAprilGrid, kCheckerboard } type = Type::kAprilGrid;
  AprilGrid grid;  // aprilgrid (grid.corner_squares: true unless the YAML says otherwise).
  // checkerboard: inner corners, corner (r, c) at (c * col_spacing_m, r * row_spacing_m, 0).
  int cols = 0, rows = 0;
  double row_spacing_m = 0, col_spacing_m = 0;
};

// Every field of `target`, doubles exactly (17 digits): equal texts, equal targets.
std::string TargetKey(const CalibrationTarget& target);

}  // namespace calibench
