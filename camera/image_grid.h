// Values on a regular grid over an image (a map of a quantity across the field: projection
// uncertainty, the difference of two calibrations). Sample (i, j), column i in [0, cols), row j in
// [0, rows), sits at pixel x = (i + 0.5) image_width / cols - 0.5, y = (j + 0.5) image_height /
// rows - 0.5, in the pixel-centre convention of camera/camera.h. NaN: no value there (outside the
// lens's field, outside the common field of two cameras).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace calibench {

struct ImageGrid {
  int image_width = 0, image_height = 0;
  int cols = 0, rows = 0;
  std::vector<double> values;  // Row-major, cols * rows.

  // A grid of `cols` columns and rows by the image's aspect ratio (at least 2 each), all NaN.
  static ImageGrid Over(int image_width, int image_height, int cols) {
    ImageGrid g;
    g.image_width = image_width;
    g.image_height = image_height;
    g.cols = std::max(2, cols);
    g.rows = std::max(2, static_cast<int>(std::lround(g.cols * static_cast<double>(image_height) /
                                                      std::max(1, image_width))));
    g.values.assign(static_cast<size_t>(g.cols) * g.rows, std::numeric_limits<double>::quiet_NaN());
    return g;
  }
  double At(int i, int j) const { return values[static_cast<size_t>(j) * cols + i]; }
  double& At(int i, int j) { return values[static_cast<size_t>(j) * cols + i]; }
  Eigen::Vector2d PixelAt(int i, int j) const {
    return {(i + 0.5) * image_width / cols - 0.5, (j + 0.5) * image_height / rows - 0.5};
  }
};

}  // namespace calibench
