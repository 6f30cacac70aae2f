// Figures of a calibration for a person to read at a glance (`calibench calibrate` writes them
// beside each camera file, `calibench compare` the projection difference): PNGs of a fixed width
// (kFigureWidthPx or HeatmapOptions::width_px) whatever the camera's resolution, the image frame
// scaled with its aspect ratio kept, a title, axes in image pixels, a colour bar with its unit.
//
// Contract: every Write* function writes `path` atomically (util/atomic_file.h) and
// returns true, or returns false with *why (if not null) naming the path and the reason (an
// unwritable path, an empty map, sizes that disagree); no exception escapes, nothing aborts.
// Only the standard library, Eigen and OpenCV (core, imgproc, imgcodecs) are used.
//
// Pixel convention: pixel (0, 0)'s centre is at (0, 0); the image spans [-0.5, width - 0.5].
// Colours: values through cv::COLORMAP_VIRIDIS (low = dark blue, high = yellow); NaN = grey.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "camera/image_grid.h"

namespace calibench {

// Width of the figures that take no options (residual vectors, per-view residuals, coverage).
constexpr int kFigureWidthPx = 960;

// The maps drawn are camera/image_grid.h's ImageGrid.
struct HeatmapOptions {
  std::string title;        // Top line of the figure.
  std::string unit = "px";  // Colour bar label.
  double max_value = 0.0;   // Colour bar top; 0: the 98th percentile of the finite values.
  std::vector<double> contour_levels;  // Empty: 4-6 "nice" levels (1-2-5 steps) within the range.
  int width_px = 960;                  // Width of the written PNG (at least 320).
};

// Where the image-frame figures (heatmap, residual vectors, coverage) draw, in the written PNG's
// pixels: for tests and for callers that annotate. The plot is the image frame scaled by
// plot_w / image_width (aspect kept); the colour bar's top row is the top of its range (for a
// heatmap HeatmapRange's hi), its bottom row the bottom (lo); the value is linear in between.
struct FigureLayout {
  int width = 0, height = 0;                           // Of the PNG.
  int plot_x = 0, plot_y = 0, plot_w = 0, plot_h = 0;  // The image frame.
  int bar_x = 0, bar_y = 0, bar_w = 0, bar_h = 0;      // The colour bar.
};
FigureLayout ImageFigureLayout(int image_width, int image_height, int width_px);

// The colour bar's range of WriteHeatmapPng: lo = 0, or the smallest finite value if negative;
// hi = options.max_value, or the 98th percentile of the finite values (above lo). false for a grid
// without a finite value.
bool HeatmapRange(const ImageGrid& grid, const HeatmapOptions& options, double* lo, double* hi);

// Writes the grid as a heatmap (bilinear upsampling of the grid to the drawn image is fine),
// contour lines with their values, `points` (pixels in the image, e.g. observed corners) as small
// dots, and a colour bar. The worst region (see below) is named in a subtitle line.
bool WriteHeatmapPng(const std::string& path, const ImageGrid& grid,
                     const std::vector<Eigen::Vector2d>& points, const HeatmapOptions& options,
                     std::string* why);

// Residual vectors: for each observed pixel, an arrow/line from the pixel along its residual
// (measured minus projected) scaled so that the 95th-percentile residual is ~3% of the image width;
// the scale stated in the figure ("arrows x N"); coloured by residual length with a colour bar.
bool WriteResidualVectorsPng(const std::string& path, int image_width, int image_height,
                             const std::vector<Eigen::Vector2d>& pixels,
                             const std::vector<Eigen::Vector2d>& residuals_px,
                             const std::string& title, std::string* why);

// Per-view residual distribution: one box (median, quartiles, 95th percentile whisker) or one
// histogram strip per view, views named on the axis (`view_names`, may be long file names:
// shorten), the RMS line of all views; x or y axis in px.
bool WriteViewResidualsPng(const std::string& path, const std::vector<std::string>& view_names,
                           const std::vector<std::vector<double>>& residual_norms_px,
                           const std::string& title, std::string* why);

// Coverage: each view's observed pixels drawn (one colour per view, a thin convex hull per view),
// and the fraction of a 10x10 grid of image cells that hold at least one point written in the
// figure. Also return that fraction through *covered_fraction if not null.
bool WriteCoveragePng(const std::string& path, int image_width, int image_height,
                      const std::vector<std::vector<Eigen::Vector2d>>& pixels_per_view,
                      const std::string& title, double* covered_fraction, std::string* why);

// The region of the image where the grid is largest, in words: "top-left corner", "top edge",
// "centre", "right edge", ... (a 3x3 split of the image; the region with the largest mean of the
// finite values), and that mean through *mean_value if not null. "" for a grid without values.
std::string WorstRegion(const ImageGrid& grid, double* mean_value);

// Image-cell coverage alone (the same 10x10 count as WriteCoveragePng), for text reports. A point
// counts in cell (floor((x + 0.5) * 10 / width), floor((y + 0.5) * 10 / height)); points outside
// the image [-0.5, size - 0.5] or not finite are ignored. 0 for an empty image size.
double CoveredFraction(int image_width, int image_height,
                       const std::vector<std::vector<Eigen::Vector2d>>& pixels_per_view);

}  // namespace calibench
