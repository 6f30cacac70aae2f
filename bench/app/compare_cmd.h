// `calibench compare A B`: two camera files of any format and lens family (io/camera_io.h)
// compared over their common field (calib/compare_cameras.h): the projection difference after the
// fitted rotation, beside their projection uncertainty where the files carry it, a verdict, and
// with --out the difference heatmap (PNG).
#pragma once

#include <limits>
#include <string>

namespace calibench {

struct CompareArgs {
  std::string a_path, b_path;
  std::string out_path;  // Difference heatmap (PNG); empty: none.
  double distance_m = std::numeric_limits<double>::infinity();  // m; infinity: rays.
  bool no_rotation = false;  // Do not fit the rotation between the camera frames.
};

// As diff(1): 0 when the cameras agree (or no uncertainty lets a verdict be made), 1 when they
// differ beyond their uncertainty; 2 for a file that cannot be read or bad arguments; 3 when --out
// cannot be written; 4 when the cameras share no field.
int Compare(const CompareArgs& args);

}  // namespace calibench
