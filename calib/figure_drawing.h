// The drawing kit of calib/calibration_pictures.cc: fonts, colours, margins, ticks, text, the
// colour map, axes and titles, contours and the atomic PNG write. Internal to calib/.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "calib/calibration_pictures.h"

namespace calibench {
namespace figure {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
inline constexpr double kTitleScale = 0.68;
inline constexpr double kTextScale = 0.48;
inline constexpr double kTickScale = 0.42;
inline const cv::Scalar kInk(40, 40, 40);
inline const cv::Scalar kSoftInk(95, 95, 95);
inline const cv::Scalar kFrame(70, 70, 70);
inline const cv::Vec3b kNoValueGrey(178, 178, 178);  // NaN cells of a heatmap.
inline const cv::Scalar kWhite(255, 255, 255);
inline const cv::Scalar kGridLine(228, 228, 228);
inline const cv::Scalar kAccent(40, 40, 215);  // Red (BGR): reference lines, observed points.
inline constexpr int kMarginTop = 86;          // Title and subtitle.
inline constexpr int kMarginLeft = 64;         // y tick labels.
inline constexpr int kMarginRight = 112;       // Colour bar and its labels.
inline constexpr int kMarginBottom = 52;       // x tick labels and the axis name.
enum class Align { kLeft, kCentre, kRight };

// Text with its baseline at y (or vertically centred on y when centre_y).
void Text(cv::Mat* img, const std::string& s, int x, int y, double scale, const cv::Scalar& colour,
          Align align = Align::kLeft, int thickness = 1, bool centre_y = false);

int TextWidth(const std::string& s, double scale, int thickness = 1);

// Shortens s to at most max_width pixels at `scale` with "..." in the middle.
std::string FitText(const std::string& s, double scale, int max_width);

double Percentile(std::vector<double> v, double p);

// A 1-2-5 step near range / target_count.
double NiceStep(double range, double target_count);

// Multiples of step in [lo, hi] (with a hair of slack for rounding).
std::vector<double> Ticks(double lo, double hi, double step);

int DecimalsFor(double step);

std::string Format(double v, int decimals);

// Three significant digits, for numbers in sentences.
std::string Sig3(double v);

// Contour levels: 4-6 multiples of a 1-2-5 step strictly inside (lo, hi).
std::vector<double> NiceLevels(double lo, double hi);

// Viridis as 256 BGR entries (cv::applyColorMap on a 0..255 ramp).
const std::vector<cv::Vec3b>& Viridis();

// The colour of t in [0, 1] (clamped), on viridis restricted to [0, top] (top < 1 keeps the
// bright yellow off light backgrounds).
cv::Vec3b ColourAt(double t, double top = 1.0);

inline cv::Scalar ToScalar(const cv::Vec3b& c) { return cv::Scalar(c[0], c[1], c[2]); }

// Qualitative colours (BGR of matplotlib's tab10, then tab20's light half) for views.
cv::Scalar ViewColour(size_t v);

// "1 point", "3 points".
std::string Count(size_t n, const std::string& noun);

bool Fail(std::string* why, const std::string& message);

bool WritePngAtomically(const std::string& path, const cv::Mat& img, std::string* why);

// The image frame's axes: a frame around the plot, ticks and labels in image pixels.
void DrawImageAxes(cv::Mat* img, const FigureLayout& L, int image_width, int image_height);

void DrawTitle(cv::Mat* img, const std::string& title, const std::string& subtitle);

// A vertical colour bar for [lo, hi] with ticks, the unit above it, optional marks (contour
// levels) and a triangle on top when values above hi were clipped. colour(t), t in [0, 1].
void DrawColourBar(cv::Mat* img, const FigureLayout& L, double lo, double hi,
                   const std::string& unit, const std::vector<double>& marks, bool clipped_high,
                   const std::function<cv::Vec3b(double)>& colour);

bool GridShapeOk(const ImageGrid& g);

std::vector<double> FiniteValues(const ImageGrid& g);

// The grid bilinearly at figure pixel (px, py) of a plot of size w x h: NaN where the finite
// neighbours weigh less than half, else the weighted mean of the finite neighbours.
double Sample(const ImageGrid& g, double px, double py, int w, int h);

// Contour lines of `values` (CV_64F, NaN = none) at `levels` drawn on `plot`, with labels placed
// away from each other and from the plot's border.
void DrawContours(cv::Mat* plot, const cv::Mat& values, const std::vector<double>& levels,
                  int decimals);

// A small dot at figure position p (sub-pixel, radius r).
void Dot(cv::Mat* img, cv::Point2d p, double r, const cv::Scalar& colour);

// Figure position of an image pixel.
cv::Point2d ToFigure(const FigureLayout& L, double s, const Eigen::Vector2d& p);

bool ImageSizeOk(const std::string& path, int w, int h, std::string* why);

// The 10x10 image cells (row-major) that hold at least one point (CoveredFraction's rule).
std::vector<bool> CoveredCells(int image_width, int image_height,
                               const std::vector<std::vector<Eigen::Vector2d>>& pixels_per_view);

}  // namespace figure
}  // namespace calibench
