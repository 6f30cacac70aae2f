// The drawing kit of the calibration figures (calib/figure_drawing.h).
#include "calib/figure_drawing.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "util/atomic_file.h"

namespace calibench {
namespace figure {

// Margins of the image-frame figures.

// Text with its baseline at y (or vertically centred on y when centre_y).
void Text(cv::Mat* img, const std::string& s, int x, int y, double scale, const cv::Scalar& colour,
          Align align, int thickness, bool centre_y) {
  int base = 0;
  const cv::Size size = cv::getTextSize(s, kFont, scale, thickness, &base);
  if (align == Align::kCentre) x -= size.width / 2;
  if (align == Align::kRight) x -= size.width;
  if (centre_y) y += size.height / 2;
  cv::putText(*img, s, cv::Point(x, y), kFont, scale, colour, thickness, cv::LINE_AA);
}

int TextWidth(const std::string& s, double scale, int thickness) {
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
cv::Vec3b ColourAt(double t, double top) {
  if (!std::isfinite(t)) return kNoValueGrey;
  const int k = static_cast<int>(std::lround(std::clamp(t, 0.0, 1.0) * top * 255.0));
  return Viridis()[std::clamp(k, 0, 255)];
}

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
  std::vector<unsigned char> png;
  try {
    if (!cv::imencode(".png", img, png)) return Fail(why, path + ": cannot encode the PNG");
  } catch (const cv::Exception& e) {
    return Fail(why, path + ": cannot encode the PNG: " + e.err);
  }
  std::string reason;
  if (!WriteFileAtomically(path, std::string(png.begin(), png.end()), &reason)) {
    return Fail(why, reason + " (does the folder exist and is it writable?)");
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
void DrawColourBar(cv::Mat* img, const FigureLayout& L, double lo, double hi,
                   const std::string& unit, const std::vector<double>& marks, bool clipped_high,
                   const std::function<cv::Vec3b(double)>& colour) {
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

}  // namespace figure
}  // namespace calibench
