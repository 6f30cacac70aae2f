// Figures of a calibration (calib/calibration_pictures.h), drawn with OpenCV's imgproc on a white
// canvas: Hershey simplex text with anti-aliasing, viridis colours, axes in image pixels.
#include "calib/calibration_pictures.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

namespace calibench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTitleScale = 0.68;
constexpr double kTextScale = 0.48;
constexpr double kTickScale = 0.42;
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kSoftInk(95, 95, 95);
const cv::Scalar kFrame(70, 70, 70);
const cv::Vec3b kNoValueGrey(178, 178, 178);  // NaN cells of a heatmap.
const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kGridLine(228, 228, 228);
const cv::Scalar kAccent(40, 40, 215);  // Red (BGR): reference lines, observed points.

// Margins of the image-frame figures.
constexpr int kMarginTop = 86;     // Title and subtitle.
constexpr int kMarginLeft = 64;    // y tick labels.
constexpr int kMarginRight = 112;  // Colour bar and its labels.
constexpr int kMarginBottom = 52;  // x tick labels and the axis name.

enum class Align { kLeft, kCentre, kRight };

// Text with its baseline at y (or vertically centred on y when centre_y).
void Text(cv::Mat* img, const std::string& s, int x, int y, double scale, const cv::Scalar& colour,
          Align align = Align::kLeft, int thickness = 1, bool centre_y = false) {
  int base = 0;
  const cv::Size size = cv::getTextSize(s, kFont, scale, thickness, &base);
  if (align == Align::kCentre) x -= size.width / 2;
  if (align == Align::kRight) x -= size.width;
  if (centre_y) y += size.height / 2;
  cv::putText(*img, s, cv::Point(x, y), kFont, scale, colour, thickness, cv::LINE_AA);
}

int TextWidth(const std::string& s, double scale, int thickness = 1) {
  int base = 0;
  return cv::getTextSize(s, kFont, scale, thickness, &base).width;
}

// Shortens s to at most max_width pixels at `scale` with "..." in the middle.
std::string FitText(const std::string& s, double scale, int max_width) {
  if (TextWidth(s, scale) <= max_width) return s;
  for (size_t keep = s.size(); keep > 4; --keep) {
    const size_t head = keep / 2, tail = keep - head;
    std::string t = s.substr(0, head) + "..." + s.substr(s.size() - tail);
    if (TextWidth(t, scale) <= max_width) return t;
  }
  return s.substr(0, 1) + "...";
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double r = std::clamp(p, 0.0, 1.0) * static_cast<double>(v.size() - 1);
  const size_t k = static_cast<size_t>(std::floor(r));
  if (k + 1 >= v.size()) return v.back();
  return v[k] + (r - static_cast<double>(k)) * (v[k + 1] - v[k]);
}

// A 1-2-5 step near range / target_count.
double NiceStep(double range, double target_count) {
  if (!(range > 0) || !std::isfinite(range)) return 1.0;
  const double raw = range / std::max(1.0, target_count);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / mag;
  const double nice = m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0;
  return nice * mag;
}

// Multiples of step in [lo, hi] (with a hair of slack for rounding).
std::vector<double> Ticks(double lo, double hi, double step) {
  std::vector<double> t;
  if (!(step > 0) || !(hi >= lo)) return t;
  const double eps = 1e-9 * step;
  for (double k = std::ceil((lo - eps) / step); k * step <= hi + eps && t.size() < 200; k += 1.0) {
    t.push_back(std::abs(k * step) < eps ? 0.0 : k * step);
  }
  return t;
}

int DecimalsFor(double step) {
  if (!(step > 0)) return 2;
  int d = 0;
  while (d < 6 && std::abs(step * std::pow(10.0, d) - std::round(step * std::pow(10.0, d))) >
                      1e-6 * step * std::pow(10.0, d)) {
    ++d;
  }
  return d;
}

std::string Format(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", std::clamp(decimals, 0, 6), v);
  std::string s = buf;
  if (s == "-0" || s.rfind("-0.", 0) == 0) {
    if (std::stod(s) == 0.0) s.erase(0, 1);
  }
  return s;
}

// Three significant digits, for numbers in sentences.
std::string Sig3(double v) {
  if (!std::isfinite(v)) return "n/a";
  const double a = std::abs(v);
  const int decimals = a == 0 ? 0 : a >= 100 ? 0 : a >= 10 ? 1 : a >= 1 ? 2 : a >= 0.1 ? 3 : 4;
  return Format(v, decimals);
}

// Contour levels: 4-6 multiples of a 1-2-5 step strictly inside (lo, hi).
std::vector<double> NiceLevels(double lo, double hi) {
  std::vector<double> best;
  int best_miss = 1 << 30;
  if (!(hi > lo)) return best;
  const int e0 = static_cast<int>(std::floor(std::log10(hi - lo)));
  for (int e = e0 - 2; e <= e0 + 1; ++e) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double step = m * std::pow(10.0, e);
      std::vector<double> levels;
      for (double v : Ticks(lo, hi, step)) {
        if (v > lo + 1e-9 * step && v < hi - 1e-9 * step) levels.push_back(v);
      }
      const int n = static_cast<int>(levels.size());
      const int miss = n >= 4 && n <= 6 ? std::abs(n - 5) : 10 + std::abs(n - 5);
      if (miss < best_miss) best_miss = miss, best = levels;
    }
  }
  return best;
}

// Viridis as 256 BGR entries (cv::applyColorMap on a 0..255 ramp).
const std::vector<cv::Vec3b>& Viridis() {
  static const std::vector<cv::Vec3b> lut = [] {
    cv::Mat ramp(1, 256, CV_8UC1), colours;
    for (int i = 0; i < 256; ++i) ramp.at<uchar>(0, i) = static_cast<uchar>(i);
    cv::applyColorMap(ramp, colours, cv::COLORMAP_VIRIDIS);
    std::vector<cv::Vec3b> v(256);
    for (int i = 0; i < 256; ++i) v[i] = colours.at<cv::Vec3b>(0, i);
    return v;
  }();
  return lut;
}

// The colour of t in [0, 1] (clamped), on viridis restricted to [0, top] (top < 1 keeps the
// bright yellow off light backgrounds).
cv::Vec3b ColourAt(double t, double top = 1.0) {
  if (!std::isfinite(t)) return kNoValueGrey;
  const int k = static_cast<int>(std::lround(std::clamp(t, 0.0, 1.0) * top * 255.0));
  return Viridis()[std::clamp(k, 0, 255)];
}

cv::Scalar ToScalar(const cv::Vec3b& c) { return cv::Scalar(c[0], c[1], c[2]); }

// Qualitative colours (BGR of matplotlib's tab10, then tab20's light half) for views.
cv::Scalar ViewColour(size_t v) {
  static const int kRgb[][3] = {{31, 119, 180},  {255, 127, 14},  {44, 160, 44},   {214, 39, 40},
                                {148, 103, 189}, {140, 86, 75},   {227, 119, 194}, {127, 127, 127},
                                {188, 189, 34},  {23, 190, 207},  {174, 199, 232}, {255, 187, 120},
                                {152, 223, 138}, {255, 152, 150}, {197, 176, 213}, {196, 156, 148},
                                {247, 182, 210}, {199, 199, 199}, {219, 219, 141}, {158, 218, 229}};
  const int* c = kRgb[v % 20];
  return cv::Scalar(c[2], c[1], c[0]);
}

// "1 point", "3 points".
std::string Count(size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

bool WritePngAtomically(const std::string& path, const cv::Mat& img, std::string* why) {
  if (path.empty()) return Fail(why, "(empty path): no file name to write the figure to");
  const std::string tmp = path + ".tmp.png";
  bool written = false;
  std::string detail;
  try {
    written = cv::imwrite(tmp, img);
  } catch (const cv::Exception& e) {
    detail = std::string(": ") + e.what();
  } catch (...) {
    detail = ": unknown error";
  }
  if (!written) {
    std::remove(tmp.c_str());
    return Fail(
        why, path + ": cannot write the PNG (does the folder exist and is it writable?)" + detail);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(tmp.c_str());
    return Fail(why, path + ": cannot rename " + tmp + " onto it: " + reason);
  }
  return true;
}

// The image frame's axes: a frame around the plot, ticks and labels in image pixels.
void DrawImageAxes(cv::Mat* img, const FigureLayout& L, int image_width, int image_height) {
  const double s = static_cast<double>(L.plot_w) / image_width;  // Figure px per image px.
  const double step = NiceStep(std::max(image_width, image_height), 8.0);
  for (double x : Ticks(0, image_width - 1, step)) {
    const int px = L.plot_x + static_cast<int>(std::lround((x + 0.5) * s));
    cv::line(*img, {px, L.plot_y + L.plot_h}, {px, L.plot_y + L.plot_h + 5}, kFrame, 1);
    Text(img, Format(x, 0), px, L.plot_y + L.plot_h + 21, kTickScale, kInk, Align::kCentre);
  }
  for (double y : Ticks(0, image_height - 1, step)) {
    const int py = L.plot_y + static_cast<int>(std::lround((y + 0.5) * s));
    cv::line(*img, {L.plot_x - 5, py}, {L.plot_x, py}, kFrame, 1);
    Text(img, Format(y, 0), L.plot_x - 9, py, kTickScale, kInk, Align::kRight, 1, true);
  }
  cv::rectangle(*img, cv::Rect(L.plot_x - 1, L.plot_y - 1, L.plot_w + 2, L.plot_h + 2), kFrame, 1);
  Text(img, "x (px)", L.plot_x + L.plot_w / 2, L.plot_y + L.plot_h + 43, kTextScale, kSoftInk,
       Align::kCentre);
  Text(img, "y (px)", L.plot_x - 9, L.plot_y - 12, kTickScale, kSoftInk, Align::kRight);
}

void DrawTitle(cv::Mat* img, const std::string& title, const std::string& subtitle) {
  const int max_w = img->cols - 24;
  Text(img, FitText(title, kTitleScale, max_w), 14, 28, kTitleScale, kInk, Align::kLeft, 2);
  Text(img, FitText(subtitle, kTextScale, max_w), 14, 54, kTextScale, kSoftInk);
}

// A vertical colour bar for [lo, hi] with ticks, the unit above it, optional marks (contour
// levels) and a triangle on top when values above hi were clipped. colour(t), t in [0, 1].
template <typename ColourFn>
void DrawColourBar(cv::Mat* img, const FigureLayout& L, double lo, double hi,
                   const std::string& unit, const std::vector<double>& marks, bool clipped_high,
                   ColourFn colour) {
  for (int r = 0; r < L.bar_h; ++r) {
    const double t = 1.0 - (r + 0.5) / L.bar_h;
    cv::line(*img, {L.bar_x, L.bar_y + r}, {L.bar_x + L.bar_w - 1, L.bar_y + r},
             ToScalar(colour(t)), 1);
  }
  const auto row_of = [&](double v) {
    return L.bar_y + static_cast<int>(std::lround((1.0 - (v - lo) / (hi - lo)) * L.bar_h - 0.5));
  };
  for (double m : marks) {
    if (m <= lo || m >= hi) continue;
    cv::line(*img, {L.bar_x, row_of(m)}, {L.bar_x + L.bar_w - 1, row_of(m)}, kWhite, 1);
  }
  cv::rectangle(*img, cv::Rect(L.bar_x - 1, L.bar_y - 1, L.bar_w + 2, L.bar_h + 2), kFrame, 1);
  if (clipped_high) {
    const cv::Point tri[3] = {{L.bar_x - 1, L.bar_y - 2},
                              {L.bar_x + L.bar_w, L.bar_y - 2},
                              {L.bar_x + L.bar_w / 2, L.bar_y - 2 - L.bar_w * 3 / 4}};
    cv::fillConvexPoly(*img, tri, 3, ToScalar(colour(1.0)), cv::LINE_AA);
    cv::polylines(*img, std::vector<cv::Point>(tri, tri + 3), true, kFrame, 1, cv::LINE_AA);
  }
  const double step = NiceStep(hi - lo, std::clamp(L.bar_h / 70.0, 3.0, 7.0));
  const int decimals = DecimalsFor(step);
  for (double v : Ticks(lo, hi, step)) {
    const int y = row_of(v);
    cv::line(*img, {L.bar_x + L.bar_w, y}, {L.bar_x + L.bar_w + 4, y}, kFrame, 1);
    Text(img, Format(v, decimals), L.bar_x + L.bar_w + 8, y, kTickScale, kInk, Align::kLeft, 1,
         true);
  }
  Text(img, unit, L.bar_x + L.bar_w / 2, L.bar_y - (clipped_high ? 22 : 10), kTextScale, kInk,
       Align::kCentre);
}

bool GridShapeOk(const ImageGrid& g) {
  return g.image_width > 0 && g.image_height > 0 && g.cols > 0 && g.rows > 0 &&
         g.values.size() == static_cast<size_t>(g.cols) * static_cast<size_t>(g.rows);
}

std::vector<double> FiniteValues(const ImageGrid& g) {
  std::vector<double> v;
  if (!GridShapeOk(g)) return v;
  for (double x : g.values) {
    if (std::isfinite(x)) v.push_back(x);
  }
  return v;
}

// The grid bilinearly at figure pixel (px, py) of a plot of size w x h: NaN where the finite
// neighbours weigh less than half, else the weighted mean of the finite neighbours.
double Sample(const ImageGrid& g, double px, double py, int w, int h) {
  const double fi = std::clamp((px + 0.5) * g.cols / w - 0.5, 0.0, g.cols - 1.0);
  const double fj = std::clamp((py + 0.5) * g.rows / h - 0.5, 0.0, g.rows - 1.0);
  const int i0 = std::min(static_cast<int>(fi), g.cols - 1);
  const int j0 = std::min(static_cast<int>(fj), g.rows - 1);
  const int i1 = std::min(i0 + 1, g.cols - 1), j1 = std::min(j0 + 1, g.rows - 1);
  const double a = fi - i0, b = fj - j0;
  const double w4[4] = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
  const double v4[4] = {g.At(i0, j0), g.At(i1, j0), g.At(i0, j1), g.At(i1, j1)};
  double sum = 0, wsum = 0;
  for (int k = 0; k < 4; ++k) {
    if (std::isfinite(v4[k])) sum += w4[k] * v4[k], wsum += w4[k];
  }
  // The no-value region's border: where the bilinear "has a value" field crosses 1/2.
  if (wsum < 0.5) return kNaN;
  return wsum > 0 ? sum / wsum : kNaN;
}

// Contour lines of `values` (CV_64F, NaN = none) at `levels` drawn on `plot`, with labels placed
// away from each other and from the plot's border.
void DrawContours(cv::Mat* plot, const cv::Mat& values, const std::vector<double>& levels,
                  int decimals) {
  const int w = values.cols, h = values.rows;
  cv::Mat nan_mask(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      nan_mask.at<uchar>(y, x) = std::isfinite(values.at<double>(y, x)) ? 0 : 255;
    }
  }
  cv::Mat near_nan;
  cv::dilate(nan_mask, near_nan, cv::Mat(), cv::Point(-1, -1), 2);
  std::vector<cv::Rect> placed;
  struct Label {
    cv::Rect box;
    std::string text;
  };
  std::vector<Label> labels;
  const cv::Scalar line_colour(250, 250, 250);
  for (double level : levels) {
    cv::Mat mask(h, w, CV_8UC1);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double v = values.at<double>(y, x);
        mask.at<uchar>(y, x) = std::isfinite(v) && v >= level ? 255 : 0;
      }
    }
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(mask, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    // Runs of each contour away from the plot's border and from no-value pixels (there the mask's
    // edge is no level line), smoothed by a moving average along the contour.
    std::vector<std::vector<cv::Point2f>> runs;
    std::vector<bool> closed_runs;
    for (const auto& c : contours) {
      const int n = static_cast<int>(c.size());
      if (n < 6) continue;
      constexpr int kHalf = 3;
      std::vector<bool> edge(n);
      int first_edge = -1;
      for (int k = 0; k < n; ++k) {
        const cv::Point& p = c[k];
        edge[k] = p.x <= 3 || p.y <= 3 || p.x >= w - 4 || p.y >= h - 4 ||
                  near_nan.at<uchar>(p.y, p.x) != 0;
        if (edge[k] && first_edge < 0) first_edge = k;
      }
      const auto at = [&](int k) { return ((k % n) + n) % n; };
      std::vector<cv::Point2f> run;
      const auto flush = [&] {
        if (run.size() >= 6) runs.push_back(run), closed_runs.push_back(false);
        run.clear();
      };
      if (first_edge < 0) {  // A closed line inside the plot.
        for (int k = 0; k < n; ++k) {
          cv::Point2f sum(0, 0);
          for (int d = -kHalf; d <= kHalf; ++d) sum += cv::Point2f(c[at(k + d)]);
          run.push_back(sum / static_cast<float>(2 * kHalf + 1));
        }
        runs.push_back(run), closed_runs.push_back(true);
        continue;
      }
      // Start at an edge point so that no run wraps around the contour's start.
      for (int m = 1; m <= n; ++m) {
        const int k = at(first_edge + m);
        bool near_edge = false;
        for (int d = -kHalf; d <= kHalf; ++d) near_edge = near_edge || edge[at(k + d)];
        if (near_edge) {
          flush();
          continue;
        }
        cv::Point2f sum(0, 0);
        for (int d = -kHalf; d <= kHalf; ++d) sum += cv::Point2f(c[at(k + d)]);
        run.push_back(sum / static_cast<float>(2 * kHalf + 1));
      }
      flush();
    }
    const std::string text = Format(level, decimals);
    int base = 0;
    const cv::Size ts = cv::getTextSize(text, kFont, kTickScale, 1, &base);
    bool labelled = false;
    std::vector<size_t> longest_first(runs.size());
    for (size_t r = 0; r < runs.size(); ++r) longest_first[r] = r;
    std::sort(longest_first.begin(), longest_first.end(),
              [&](size_t a, size_t b) { return runs[a].size() > runs[b].size(); });
    for (size_t r : longest_first) {
      const auto& run = runs[r];
      std::vector<cv::Point> pts;
      for (const auto& p : run)
        pts.emplace_back(cv::Point(std::lround(p.x * 8), std::lround(p.y * 8)));
      cv::polylines(*plot, pts, closed_runs[r], line_colour, 1, cv::LINE_AA, 3);
      if (labelled || run.size() < 40) continue;
      // The candidate along the line farthest from the labels already placed (the line's middle
      // for the first label), clear of them and of the plot's border.
      double best_score = -1;
      cv::Rect best_box;
      for (int step = 1; step < 10; ++step) {
        const double f = step / 10.0;
        const cv::Point2f c = run[static_cast<size_t>(f * (run.size() - 1))];
        const cv::Rect box(static_cast<int>(c.x) - ts.width / 2 - 3,
                           static_cast<int>(c.y) - ts.height / 2 - 3, ts.width + 6, ts.height + 6);
        if (box.x < 4 || box.y < 4 || box.x + box.width > w - 4 || box.y + box.height > h - 4) {
          continue;
        }
        double score = 1e9 - std::abs(f - 0.5);
        for (const auto& other : placed) {
          if ((other & cv::Rect(box.x - 6, box.y - 6, box.width + 12, box.height + 12)).area() >
              0) {
            score = -1;
            break;
          }
          const cv::Point2f d(other.x + other.width / 2.0f - c.x,
                              other.y + other.height / 2.0f - c.y);
          score = std::min(score, static_cast<double>(std::hypot(d.x, d.y)));
        }
        if (score > best_score) best_score = score, best_box = box;
      }
      if (best_score < 0) continue;
      placed.push_back(best_box);
      labels.push_back({best_box, text});
      labelled = true;
    }
  }
  for (const auto& l : labels) {
    cv::Mat roi = (*plot)(l.box);
    cv::Mat white(roi.size(), roi.type(), kWhite);
    cv::addWeighted(roi, 0.25, white, 0.75, 0.0, roi);
    Text(plot, l.text, l.box.x + l.box.width / 2, l.box.y + l.box.height / 2, kTickScale, kInk,
         Align::kCentre, 1, true);
  }
}

// A small dot at figure position p (sub-pixel, radius r).
void Dot(cv::Mat* img, cv::Point2d p, double r, const cv::Scalar& colour) {
  cv::circle(*img, cv::Point(std::lround(p.x * 16), std::lround(p.y * 16)),
             static_cast<int>(std::lround(r * 16)), colour, cv::FILLED, cv::LINE_AA, 4);
}

// Figure position of an image pixel.
cv::Point2d ToFigure(const FigureLayout& L, double s, const Eigen::Vector2d& p) {
  return {L.plot_x + (p.x() + 0.5) * s - 0.5, L.plot_y + (p.y() + 0.5) * s - 0.5};
}

bool ImageSizeOk(const std::string& path, int w, int h, std::string* why) {
  if (w > 0 && h > 0) return true;
  return Fail(why, path + ": image size " + std::to_string(w) + " x " + std::to_string(h) +
                       " is not positive");
}

// The 10x10 image cells (row-major) that hold at least one point (CoveredFraction's rule).
std::vector<bool> CoveredCells(int image_width, int image_height,
                               const std::vector<std::vector<Eigen::Vector2d>>& pixels_per_view) {
  std::vector<bool> cell(100, false);
  if (image_width <= 0 || image_height <= 0) return cell;
  for (const auto& view : pixels_per_view) {
    for (const auto& p : view) {
      if (!p.allFinite() || p.x() < -0.5 || p.y() < -0.5 || p.x() > image_width - 0.5 ||
          p.y() > image_height - 0.5) {
        continue;
      }
      const int cx = std::min(9, static_cast<int>(std::floor((p.x() + 0.5) * 10 / image_width)));
      const int cy = std::min(9, static_cast<int>(std::floor((p.y() + 0.5) * 10 / image_height)));
      cell[cy * 10 + cx] = true;
    }
  }
  return cell;
}

}  // namespace

FigureLayout ImageFigureLayout(int image_width, int image_height, int width_px) {
  FigureLayout L;
  L.width = std::max(width_px, 320);
  L.plot_x = kMarginLeft;
  L.plot_y = kMarginTop;
  L.plot_w = L.width - kMarginLeft - kMarginRight;
  const double aspect =
      image_width > 0 && image_height > 0 ? static_cast<double>(image_height) / image_width : 0.75;
  L.plot_h = std::max(1, static_cast<int>(std::lround(L.plot_w * aspect)));
  L.height = kMarginTop + L.plot_h + kMarginBottom;
  L.bar_x = L.plot_x + L.plot_w + 26;
  L.bar_w = 16;
  L.bar_y = L.plot_y;
  L.bar_h = L.plot_h;
  return L;
}

bool HeatmapRange(const ImageGrid& grid, const HeatmapOptions& options, double* lo, double* hi) {
  const std::vector<double> v = FiniteValues(grid);
  if (v.empty()) return false;
  const double vmin = *std::min_element(v.begin(), v.end());
  const double l = std::min(0.0, vmin);
  double h = options.max_value > 0 && std::isfinite(options.max_value) ? options.max_value
                                                                       : Percentile(v, 0.98);
  if (!(h > l)) h = l + (std::abs(l) > 0 ? 0.1 * std::abs(l) : 1.0);
  if (lo) *lo = l;
  if (hi) *hi = h;
  return true;
}

std::string WorstRegion(const ImageGrid& grid, double* mean_value) {
  if (!GridShapeOk(grid)) return "";
  double sum[9] = {0}, count[9] = {0};
  for (int j = 0; j < grid.rows; ++j) {
    for (int i = 0; i < grid.cols; ++i) {
      const double v = grid.At(i, j);
      if (!std::isfinite(v)) continue;
      const Eigen::Vector2d p = grid.PixelAt(i, j);
      const int rx =
          std::clamp(static_cast<int>(std::floor((p.x() + 0.5) * 3 / grid.image_width)), 0, 2);
      const int ry =
          std::clamp(static_cast<int>(std::floor((p.y() + 0.5) * 3 / grid.image_height)), 0, 2);
      sum[ry * 3 + rx] += v;
      count[ry * 3 + rx] += 1;
    }
  }
  static const char* kNames[9] = {"top-left corner",    "top edge",    "top-right corner",
                                  "left edge",          "centre",      "right edge",
                                  "bottom-left corner", "bottom edge", "bottom-right corner"};
  int best = -1;
  double best_mean = -std::numeric_limits<double>::infinity();
  for (int r = 0; r < 9; ++r) {
    if (count[r] > 0 && sum[r] / count[r] > best_mean) best = r, best_mean = sum[r] / count[r];
  }
  if (best < 0) return "";
  if (mean_value) *mean_value = best_mean;
  return kNames[best];
}

double CoveredFraction(int image_width, int image_height,
                       const std::vector<std::vector<Eigen::Vector2d>>& pixels_per_view) {
  const std::vector<bool> cells = CoveredCells(image_width, image_height, pixels_per_view);
  return static_cast<double>(std::count(cells.begin(), cells.end(), true)) / 100.0;
}

bool WriteHeatmapPng(const std::string& path, const ImageGrid& grid,
                     const std::vector<Eigen::Vector2d>& points, const HeatmapOptions& options,
                     std::string* why) {
  try {
    if (!GridShapeOk(grid)) {
      return Fail(why, path + ": empty or malformed map (image " +
                           std::to_string(grid.image_width) + " x " +
                           std::to_string(grid.image_height) + ", grid " +
                           std::to_string(grid.cols) + " x " + std::to_string(grid.rows) + ", " +
                           std::to_string(grid.values.size()) + " values)");
    }
    double lo = 0, hi = 1;
    if (!HeatmapRange(grid, options, &lo, &hi)) {
      return Fail(why, path + ": empty map (no finite value in the " + std::to_string(grid.cols) +
                           " x " + std::to_string(grid.rows) + " grid)");
    }
    const std::vector<double> finite = FiniteValues(grid);
    const double vmax = *std::max_element(finite.begin(), finite.end());
    const FigureLayout L = ImageFigureLayout(grid.image_width, grid.image_height, options.width_px);
    cv::Mat img(L.height, L.width, CV_8UC3, kWhite);

    cv::Mat values(L.plot_h, L.plot_w, CV_64F);
    cv::Mat plot(L.plot_h, L.plot_w, CV_8UC3);
    bool any_nan = false;
    for (int y = 0; y < L.plot_h; ++y) {
      for (int x = 0; x < L.plot_w; ++x) {
        const double v = Sample(grid, x, y, L.plot_w, L.plot_h);
        values.at<double>(y, x) = v;
        if (!std::isfinite(v)) {
          any_nan = true;
          plot.at<cv::Vec3b>(y, x) = kNoValueGrey;
        } else {
          plot.at<cv::Vec3b>(y, x) = ColourAt((v - lo) / (hi - lo));
        }
      }
    }
    std::vector<double> levels = options.contour_levels;
    const bool auto_levels = levels.empty();
    if (auto_levels) levels = NiceLevels(lo, std::min(hi, vmax));
    int decimals = 0;
    if (auto_levels && levels.size() >= 2) {
      decimals = DecimalsFor(levels[1] - levels[0]);
    } else {
      for (double l : levels) decimals = std::max(decimals, DecimalsFor(std::abs(l)));
      decimals = std::min(decimals, 3);
    }
    DrawContours(&plot, values, levels, decimals);
    const double s = static_cast<double>(L.plot_w) / grid.image_width;
    for (const auto& p : points) {
      if (!p.allFinite()) continue;
      const cv::Point2d q((p.x() + 0.5) * s - 0.5, (p.y() + 0.5) * s - 0.5);
      if (q.x < -2 || q.y < -2 || q.x > L.plot_w + 1 || q.y > L.plot_h + 1) continue;
      Dot(&plot, q, 1.9, cv::Scalar(255, 255, 255));
      Dot(&plot, q, 1.3, kAccent);
    }
    plot.copyTo(img(cv::Rect(L.plot_x, L.plot_y, L.plot_w, L.plot_h)));
    DrawImageAxes(&img, L, grid.image_width, grid.image_height);
    DrawColourBar(&img, L, lo, hi, options.unit, levels, vmax > hi,
                  [](double t) { return ColourAt(t); });

    double worst_mean = kNaN;
    const std::string region = WorstRegion(grid, &worst_mean);
    std::string subtitle = "Largest in the " + region + " (mean " + Sig3(worst_mean) + " " +
                           options.unit + "); max " + Sig3(vmax) + " " + options.unit;
    if (!points.empty()) {
      subtitle += "; red dots: " + Count(points.size(), "point");
    }
    if (any_nan) subtitle += "; grey: no value";
    DrawTitle(&img, options.title, subtitle);
    return WritePngAtomically(path, img, why);
  } catch (const std::exception& e) {
    return Fail(why, path + ": " + e.what());
  }
}

bool WriteResidualVectorsPng(const std::string& path, int image_width, int image_height,
                             const std::vector<Eigen::Vector2d>& pixels,
                             const std::vector<Eigen::Vector2d>& residuals_px,
                             const std::string& title, std::string* why) {
  try {
    if (!ImageSizeOk(path, image_width, image_height, why)) return false;
    if (pixels.size() != residuals_px.size()) {
      return Fail(why, path + ": " + std::to_string(pixels.size()) + " pixels but " +
                           std::to_string(residuals_px.size()) + " residuals");
    }
    std::vector<size_t> order;
    std::vector<double> norms;
    for (size_t k = 0; k < pixels.size(); ++k) {
      if (pixels[k].allFinite() && residuals_px[k].allFinite()) {
        order.push_back(k);
        norms.push_back(residuals_px[k].norm());
      }
    }
    if (order.empty()) return Fail(why, path + ": no residual to draw (no finite pair)");
    const double p95 = Percentile(norms, 0.95);
    double sum2 = 0;
    for (double n : norms) sum2 += n * n;
    const double rms = std::sqrt(sum2 / norms.size());
    // Arrow scale: a 1-2-5 number near 3% of the width over the 95th percentile.
    const double raw_scale = p95 > 0 ? 0.03 * image_width / p95 : 1.0;
    const double scale = NiceStep(raw_scale, 1.0);
    double hi = Percentile(norms, 0.98);
    if (!(hi > 0)) hi = 1.0;
    const double kMarginTop = 0.88;  // Viridis up to yellow-green: visible on white.

    const FigureLayout L = ImageFigureLayout(image_width, image_height, kFigureWidthPx);
    cv::Mat img(L.height, L.width, CV_8UC3, kWhite);
    cv::rectangle(img, cv::Rect(L.plot_x, L.plot_y, L.plot_w, L.plot_h), cv::Scalar(250, 250, 250),
                  cv::FILLED);
    const double s = static_cast<double>(L.plot_w) / image_width;
    const double grid_step = NiceStep(std::max(image_width, image_height), 8.0);
    for (double x : Ticks(0, image_width - 1, grid_step)) {
      const int px = L.plot_x + static_cast<int>(std::lround((x + 0.5) * s));
      cv::line(img, {px, L.plot_y}, {px, L.plot_y + L.plot_h - 1}, kGridLine, 1);
    }
    for (double y : Ticks(0, image_height - 1, grid_step)) {
      const int py = L.plot_y + static_cast<int>(std::lround((y + 0.5) * s));
      cv::line(img, {L.plot_x, py}, {L.plot_x + L.plot_w - 1, py}, kGridLine, 1);
    }
    std::vector<size_t> idx(order.size());
    for (size_t k = 0; k < idx.size(); ++k) idx[k] = k;
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return norms[a] < norms[b]; });
    cv::Mat plot = img(cv::Rect(L.plot_x, L.plot_y, L.plot_w, L.plot_h));
    const FigureLayout P{L.plot_w, L.plot_h, 0, 0, L.plot_w, L.plot_h, 0, 0, 0, 0};
    for (size_t k : idx) {
      const Eigen::Vector2d& p = pixels[order[k]];
      const Eigen::Vector2d e = p + scale * residuals_px[order[k]];
      const cv::Point2d a = ToFigure(P, s, p), b = ToFigure(P, s, e);
      const cv::Scalar c = ToScalar(ColourAt(norms[k] / hi, kMarginTop));
      Dot(&plot, a, 1.2, c);
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      if (len < 0.5) continue;
      const double tip = std::min(0.35, 5.0 / len);
      cv::arrowedLine(plot, cv::Point(std::lround(a.x * 8), std::lround(a.y * 8)),
                      cv::Point(std::lround(b.x * 8), std::lround(b.y * 8)), c, 1, cv::LINE_AA, 3,
                      tip);
    }
    DrawImageAxes(&img, L, image_width, image_height);
    DrawColourBar(&img, L, 0.0, hi, "px", {},
                  norms.empty() ? false : *std::max_element(norms.begin(), norms.end()) > hi,
                  [&](double t) { return ColourAt(t, kMarginTop); });
    const std::string subtitle = Count(norms.size(), "residual") + ", RMS " + Sig3(rms) +
                                 " px, 95th percentile " + Sig3(p95) + " px; arrows x " +
                                 Format(scale, DecimalsFor(scale)) + " (key:";
    DrawTitle(&img, title, subtitle);
    // The key arrow after the subtitle: a residual of the 95th percentile's nice value.
    const double key = NiceStep(p95 > 0 ? p95 : 1.0, 1.0);
    const int x0 = 14 + TextWidth(subtitle, kTextScale) + 8;
    const int key_len = std::max(4, static_cast<int>(std::lround(key * scale * s)));
    const cv::Scalar kc = ToScalar(ColourAt(key / hi, kMarginTop));
    cv::arrowedLine(img, {x0, 50}, {x0 + key_len, 50}, kc, 2, cv::LINE_AA, 0,
                    std::min(0.4, 7.0 / key_len));
    Text(&img, Format(key, DecimalsFor(key)) + " px)", x0 + key_len + 6, 54, kTextScale, kSoftInk);
    return WritePngAtomically(path, img, why);
  } catch (const std::exception& e) {
    return Fail(why, path + ": " + e.what());
  }
}

bool WriteViewResidualsPng(const std::string& path, const std::vector<std::string>& view_names,
                           const std::vector<std::vector<double>>& residual_norms_px,
                           const std::string& title, std::string* why) {
  try {
    const size_t n = residual_norms_px.size();
    if (n == 0) return Fail(why, path + ": no view to draw");
    if (view_names.size() != n) {
      return Fail(why, path + ": " + std::to_string(view_names.size()) + " view names but " +
                           std::to_string(n) + " views of residuals");
    }
    struct Stats {
      double p5, q1, med, q3, p95;
      std::vector<double> v;
    };
    std::vector<Stats> stats(n);
    double sum2 = 0, count = 0, xmax = 0;
    for (size_t k = 0; k < n; ++k) {
      for (double r : residual_norms_px[k]) {
        if (std::isfinite(r)) stats[k].v.push_back(std::abs(r));
      }
      const auto& v = stats[k].v;
      for (double r : v) sum2 += r * r, count += 1;
      stats[k].p5 = Percentile(v, 0.05), stats[k].q1 = Percentile(v, 0.25);
      stats[k].med = Percentile(v, 0.5), stats[k].q3 = Percentile(v, 0.75);
      stats[k].p95 = Percentile(v, 0.95);
      if (!v.empty()) xmax = std::max(xmax, stats[k].p95);
    }
    if (count == 0) return Fail(why, path + ": no finite residual in any view");
    const double rms = std::sqrt(sum2 / count);
    xmax = std::max(xmax * 1.2, rms * 1.3);
    if (!(xmax > 0)) xmax = 1.0;
    const double step = NiceStep(xmax, 6.0);
    xmax = std::ceil(xmax / step - 1e-9) * step;

    // Names: the file name without folder and extension, fitted to the left margin.
    const int row_h = std::clamp(620 / static_cast<int>(n), 11, 28);
    const double name_scale = row_h >= 18 ? kTickScale : 0.36;
    const int label_every = row_h >= 13 ? 1 : (13 + row_h - 1) / row_h;
    constexpr int kNameWidth = 190;
    std::vector<std::string> names(n);
    for (size_t k = 0; k < n; ++k) {
      std::string s = view_names[k];
      const size_t slash = s.find_last_of("/\\");
      if (slash != std::string::npos && slash + 1 < s.size()) s = s.substr(slash + 1);
      const size_t dot = s.find_last_of('.');
      if (dot != std::string::npos && dot > 0) s = s.substr(0, dot);
      if (s.empty()) s = "view " + std::to_string(k + 1);
      names[k] = s;
    }
    // Long names: the part common to all names is elided first (suffix, then prefix), so the
    // part that tells views apart stays.
    size_t prefix = names[0].size(), suffix = names[0].size();
    for (const auto& s : names) {
      size_t p = 0, q = 0;
      while (p < std::min(prefix, s.size()) && s[p] == names[0][p]) ++p;
      while (q < std::min(suffix, s.size()) &&
             s[s.size() - 1 - q] == names[0][names[0].size() - 1 - q])
        ++q;
      prefix = p, suffix = q;
    }
    int name_w = 0;
    for (auto& s : names) {
      if (n > 1 && TextWidth(s, name_scale) > kNameWidth && suffix > 3 &&
          suffix + prefix < s.size()) {
        s = s.substr(0, s.size() - suffix) + "...";
      }
      if (n > 1 && TextWidth(s, name_scale) > kNameWidth && prefix > 6) {
        s = "..." + s.substr(prefix - 4);
      }
      s = FitText(s, name_scale, kNameWidth);
      name_w = std::max(name_w, TextWidth(s, name_scale));
    }
    const int W = kFigureWidthPx;
    const int px0 = std::max(60, name_w + 22), px1 = W - 40;
    const int py0 = 92, plot_h = row_h * static_cast<int>(n);
    const int H = py0 + plot_h + 56;
    cv::Mat img(H, W, CV_8UC3, kWhite);
    const auto X = [&](double v) { return px0 + std::clamp(v / xmax, 0.0, 1.0) * (px1 - px0); };
    const int decimals = DecimalsFor(step);
    for (double t : Ticks(0, xmax, step)) {
      const int x = static_cast<int>(std::lround(X(t)));
      cv::line(img, {x, py0}, {x, py0 + plot_h}, kGridLine, 1);
      cv::line(img, {x, py0 + plot_h}, {x, py0 + plot_h + 5}, kFrame, 1);
      Text(&img, Format(t, decimals), x, py0 + plot_h + 21, kTickScale, kInk, Align::kCentre);
    }
    // Which names to write: all if the rows are tall enough, else every label_every-th and the
    // flagged views (median above kFlagFactor times the median of the views' medians; in red)
    // with their neighbours' names left out.
    constexpr double kFlagFactor = 2.0;
    std::vector<double> medians;
    for (const auto& st : stats) {
      if (!st.v.empty()) medians.push_back(st.med);
    }
    const double median_of_medians = Percentile(medians, 0.5);
    std::vector<bool> flagged(n, false), labelled(n, false);
    for (size_t k = 0; k < n; ++k) {
      flagged[k] = !stats[k].v.empty() && stats[k].med > kFlagFactor * median_of_medians;
      labelled[k] = k % label_every == 0;
    }
    for (size_t k = 0; k < n && label_every > 1; ++k) {
      if (!flagged[k]) continue;
      for (size_t d = 1; d < static_cast<size_t>(label_every); ++d) {
        if (k >= d && !flagged[k - d]) labelled[k - d] = false;
        if (k + d < n && !flagged[k + d]) labelled[k + d] = false;
      }
    }
    for (size_t k = 0; k < n; ++k) labelled[k] = labelled[k] || flagged[k];
    const cv::Scalar box_fill(235, 206, 160), box_edge(140, 80, 30), median_colour(90, 40, 10);
    for (size_t k = 0; k < n; ++k) {
      const int yc = py0 + static_cast<int>(k) * row_h + row_h / 2;
      if (k % 2 == 1) {
        cv::rectangle(img, cv::Rect(px0, py0 + static_cast<int>(k) * row_h, px1 - px0, row_h),
                      cv::Scalar(248, 248, 248), cv::FILLED);
      }
      if (labelled[k]) {
        Text(&img, names[k], px0 - 10, yc, name_scale, flagged[k] ? kAccent : kInk, Align::kRight,
             1, true);
      }
      const Stats& st = stats[k];
      if (st.v.empty()) {
        Text(&img, "no points", px0 + 8, yc, 0.36, kSoftInk, Align::kLeft, 1, true);
        continue;
      }
      const int half = std::max(2, static_cast<int>(row_h * 0.3));
      const auto xi = [&](double v) { return static_cast<int>(std::lround(X(v))); };
      cv::line(img, {xi(st.p5), yc}, {xi(st.q1), yc}, box_edge, 1, cv::LINE_AA);
      cv::line(img, {xi(st.q3), yc}, {xi(st.p95), yc}, box_edge, 1, cv::LINE_AA);
      cv::line(img, {xi(st.p5), yc - half / 2}, {xi(st.p5), yc + half / 2}, box_edge, 1);
      cv::line(img, {xi(st.p95), yc - half / 2}, {xi(st.p95), yc + half / 2}, box_edge, 1);
      const cv::Rect box(xi(st.q1), yc - half, std::max(1, xi(st.q3) - xi(st.q1)), 2 * half + 1);
      cv::rectangle(img, box, box_fill, cv::FILLED);
      cv::rectangle(img, box, box_edge, 1);
      cv::line(img, {xi(st.med), yc - half}, {xi(st.med), yc + half}, median_colour, 2);
      for (double r : st.v) {
        if (r <= st.p95) continue;
        if (r > xmax) {
          const cv::Point tri[3] = {{px1 - 1, yc}, {px1 - 7, yc - 3}, {px1 - 7, yc + 3}};
          cv::fillConvexPoly(img, tri, 3, box_edge, cv::LINE_AA);
        } else {
          Dot(&img, {X(r), static_cast<double>(yc)}, 1.5, box_edge);
        }
      }
    }
    cv::rectangle(img, cv::Rect(px0 - 1, py0 - 1, px1 - px0 + 2, plot_h + 2), kFrame, 1);
    // The RMS of all residuals: a dashed red line across all views.
    const int xr = static_cast<int>(std::lround(X(rms)));
    for (int y = py0; y < py0 + plot_h; y += 8) {
      cv::line(img, {xr, y}, {xr, std::min(y + 4, py0 + plot_h - 1)}, kAccent, 2);
    }
    Text(&img, "RMS " + Sig3(rms) + " px", xr, py0 - 8, kTickScale, kAccent, Align::kCentre);
    Text(&img, "residual norm (px)", (px0 + px1) / 2, py0 + plot_h + 44, kTextScale, kSoftInk,
         Align::kCentre);
    std::string subtitle = Count(n, "view") + ", " + Count(static_cast<size_t>(count), "point") +
                           "; box: quartiles, median; whiskers: 5th-95th percentile";
    if (std::count(flagged.begin(), flagged.end(), true) > 0) {
      subtitle += "; red: median > 2 x the views' median";
    }
    DrawTitle(&img, title, subtitle);
    return WritePngAtomically(path, img, why);
  } catch (const std::exception& e) {
    return Fail(why, path + ": " + e.what());
  }
}

bool WriteCoveragePng(const std::string& path, int image_width, int image_height,
                      const std::vector<std::vector<Eigen::Vector2d>>& pixels_per_view,
                      const std::string& title, double* covered_fraction, std::string* why) {
  try {
    const double fraction = CoveredFraction(image_width, image_height, pixels_per_view);
    if (covered_fraction) *covered_fraction = fraction;
    if (!ImageSizeOk(path, image_width, image_height, why)) return false;
    const FigureLayout L = ImageFigureLayout(image_width, image_height, kFigureWidthPx);
    cv::Mat img(L.height, L.width, CV_8UC3, kWhite);
    const double s = static_cast<double>(L.plot_w) / image_width;
    const std::vector<bool> cells = CoveredCells(image_width, image_height, pixels_per_view);
    // Cells: covered white, empty tinted red; the 10x10 grid in light lines.
    for (int cy = 0; cy < 10; ++cy) {
      for (int cx = 0; cx < 10; ++cx) {
        const int x0 = L.plot_x + static_cast<int>(std::lround(cx * L.plot_w / 10.0));
        const int x1 = L.plot_x + static_cast<int>(std::lround((cx + 1) * L.plot_w / 10.0));
        const int y0 = L.plot_y + static_cast<int>(std::lround(cy * L.plot_h / 10.0));
        const int y1 = L.plot_y + static_cast<int>(std::lround((cy + 1) * L.plot_h / 10.0));
        const bool covered = cells[cy * 10 + cx];
        cv::rectangle(img, cv::Rect(x0, y0, x1 - x0, y1 - y0),
                      covered ? kWhite : cv::Scalar(222, 226, 250), cv::FILLED);
        cv::rectangle(img, cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1), kGridLine, 1);
      }
    }
    cv::Mat plot = img(cv::Rect(L.plot_x, L.plot_y, L.plot_w, L.plot_h));
    const FigureLayout P{L.plot_w, L.plot_h, 0, 0, L.plot_w, L.plot_h, 0, 0, 0, 0};
    size_t points = 0;
    for (size_t v = 0; v < pixels_per_view.size(); ++v) {
      const cv::Scalar c = ViewColour(v);
      std::vector<cv::Point2f> pts;
      for (const auto& p : pixels_per_view[v]) {
        if (!p.allFinite()) continue;
        const cv::Point2d q = ToFigure(P, s, p);
        pts.emplace_back(static_cast<float>(q.x), static_cast<float>(q.y));
        Dot(&plot, q, 1.6, c);
        ++points;
      }
      if (pts.size() >= 3) {
        std::vector<cv::Point2f> hull;
        cv::convexHull(pts, hull);
        std::vector<cv::Point> h8;
        h8.reserve(hull.size());
        for (const auto& p : hull) h8.emplace_back(std::lround(p.x * 8), std::lround(p.y * 8));
        cv::polylines(plot, h8, true, c, 1, cv::LINE_AA, 3);
      }
    }
    DrawImageAxes(&img, L, image_width, image_height);
    // Legend in the right margin: views' colours (the first ones).
    const int lx = L.plot_x + L.plot_w + 16;
    int ly = L.plot_y + 6;
    Text(&img, "views", lx, ly, kTickScale, kInk);
    ly += 18;
    const size_t shown =
        std::min<size_t>(pixels_per_view.size(), std::max(1, (L.plot_h - 60) / 17));
    for (size_t v = 0; v < shown; ++v, ly += 17) {
      cv::rectangle(img, cv::Rect(lx, ly - 9, 10, 10), ViewColour(v), cv::FILLED);
      Text(&img, std::to_string(v + 1), lx + 16, ly, kTickScale, kInk);
    }
    if (shown < pixels_per_view.size()) {
      Text(&img, "+" + std::to_string(pixels_per_view.size() - shown) + " more", lx, ly, kTickScale,
           kSoftInk);
      ly += 17;
    }
    cv::rectangle(img, cv::Rect(lx, ly + 4, 10, 10), cv::Scalar(222, 226, 250), cv::FILLED);
    cv::rectangle(img, cv::Rect(lx, ly + 4, 10, 10), kGridLine, 1);
    Text(&img, "empty", lx + 16, ly + 13, kTickScale, kInk);
    char pct[32];
    std::snprintf(pct, sizeof(pct), "%.0f%%", fraction * 100.0);
    const std::string subtitle = std::string("Covered: ") + pct + " of the 10 x 10 image cells (" +
                                 std::to_string(static_cast<int>(std::lround(fraction * 100))) +
                                 " of 100) hold a point; " + Count(pixels_per_view.size(), "view") +
                                 ", " + Count(points, "point");
    DrawTitle(&img, title, subtitle);
    return WritePngAtomically(path, img, why);
  } catch (const std::exception& e) {
    return Fail(why, path + ": " + e.what());
  }
}

}  // namespace calibench
