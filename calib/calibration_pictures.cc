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

#include "calib/figure_drawing.h"

namespace calibench {

using figure::Align;
using figure::ColourAt;
using figure::Count;
using figure::CoveredCells;
using figure::DecimalsFor;
using figure::Dot;
using figure::DrawColourBar;
using figure::DrawContours;
using figure::DrawImageAxes;
using figure::DrawTitle;
using figure::Fail;
using figure::FiniteValues;
using figure::FitText;
using figure::Format;
using figure::GridShapeOk;
using figure::ImageSizeOk;
using figure::kAccent;
using figure::kFrame;
using figure::kGridLine;
using figure::kInk;
using figure::kMarginBottom;
using figure::kMarginLeft;
using figure::kMarginRight;
using figure::kMarginTop;
using figure::kNaN;
using figure::kNoValueGrey;
using figure::kSoftInk;
using figure::kTextScale;
using figure::kTickScale;
using figure::kWhite;
using figure::NiceLevels;
using figure::NiceStep;
using figure::Percentile;
using figure::Sample;
using figure::Sig3;
using figure::Text;
using figure::TextWidth;
using figure::Ticks;
using figure::ToFigure;
using figure::ToScalar;
using figure::ViewColour;
using figure::Viridis;
using figure::WritePngAtomically;

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
    const double kColourTop = 0.88;  // Viridis up to yellow-green: visible on white.

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
      const cv::Scalar c = ToScalar(ColourAt(norms[k] / hi, kColourTop));
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
                  [&](double t) { return ColourAt(t, kColourTop); });
    const std::string subtitle = Count(norms.size(), "residual") + ", RMS " + Sig3(rms) +
                                 " px, 95th percentile " + Sig3(p95) + " px; arrows x " +
                                 Format(scale, DecimalsFor(scale)) + " (key:";
    DrawTitle(&img, title, subtitle);
    // The key arrow after the subtitle: a residual of the 95th percentile's nice value.
    const double key = NiceStep(p95 > 0 ? p95 : 1.0, 1.0);
    const int x0 = 14 + TextWidth(subtitle, kTextScale) + 8;
    const int key_len = std::max(4, static_cast<int>(std::lround(key * scale * s)));
    const cv::Scalar kc = ToScalar(ColourAt(key / hi, kColourTop));
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
