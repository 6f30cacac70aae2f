#include "calib/calibration_target.h"

#include <cstdio>

namespace calibench {

std::string TargetKey(const CalibrationTarget& t) {
  char text[512];
  const AprilGrid& g = t.grid;
  std::snprintf(text, sizeof(text),
                "type %d; grid %s %d x %d, size %.17g, spacing %.17g, first id %d, border %d, "
                "corner squares %d; checkerboard %d x %d, spacing %.17g x %.17g",
                static_cast<int>(t.type), g.family.c_str(), g.tag_rows, g.tag_cols, g.tag_size_m,
                g.tag_spacing, g.first_id, g.black_tag_border, g.corner_squares ? 1 : 0, t.cols,
                t.rows, t.row_spacing_m, t.col_spacing_m);
  return text;
}

}  // namespace calibench
