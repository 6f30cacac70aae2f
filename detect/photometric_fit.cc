#include "detect/photometric_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace calibench {
namespace {

constexpr int kNumParams = 13;  // G (8), sigma, black, white, shading (2).
constexpr int kSigma = 8, kBlack = 9, kWhite = 10, kShadeX = 11, kShadeY = 12;
using ParamVector = Eigen::Matrix<double, kNumParams, 1>;
using ParamMatrix = Eigen::Matrix<double, kNumParams, kNumParams>;
constexpr double kMinSigmaPx = 0.02;
constexpr double kReclassifyPx = 0.5;
constexpr double kReclassifySigmaPx = 0.1;  // Sigma may grow this much before (reach + 0.35 px).
constexpr int kMaxLinesPerPixel = 32;       // Cells of >= 1 px: a pixel is near far fewer.
constexpr double kInvSqrt2 = 0.70710678118654752440;
constexpr double kInvSqrt2Pi = 0.39894228040143267794;

double Phi(double u) { return 0.5 * std::erfc(-u * kInvSqrt2); }
double PhiDensity(double u) { return kInvSqrt2Pi * std::exp(-0.5 * u * u); }

// Reach of the profile: beyond it, P is 0 or 1 to < 3e-4 of the contrast (3.5 sigma of the PSF plus
// the pixel box's half diagonal).
double ProfileReachPx(double sigma) { return 3.5 * sigma + 0.75; }

// P, dP/dd and dP/dsigma tabulated on a fine grid for one sigma and one edge direction (the lines
// of one family of a tag are nearly parallel in the image: one table per family).
class ProfileTable {
 public:
  void Build(double sigma, const Eigen::Vector2d& normal) {
    reach_ = ProfileReachPx(sigma);
    const int n = static_cast<int>(std::ceil(2 * reach_ * kPerPx)) + 1;
    values_.resize(n);
    for (int i = 0; i < n; ++i) {
      values_[i] = EdgeProfile(-reach_ + i / kPerPx, sigma, normal.x(), normal.y());
    }
  }
  // P by cubic Hermite interpolation from the nodes' P and P' (error ~ h^4 P'''' / 384: < 1e-5 of
  // the contrast), P' and dP/dsigma linearly (they enter the Jacobian only).
  EdgeProfileValue operator()(double d) const {
    const double t = (d + reach_) * kPerPx;
    if (!(t > 0)) return {0, 0, 0};  // Also NaN: no cast of a non-finite value below.
    if (!(t < static_cast<double>(values_.size() - 1))) return {1, 0, 0};
    const int i = static_cast<int>(t);
    const double f = t - i, f2 = f * f, f3 = f2 * f;
    const EdgeProfileValue& a = values_[i];
    const EdgeProfileValue& b = values_[i + 1];
    constexpr double h = 1.0 / kPerPx;
    const double p = (2 * f3 - 3 * f2 + 1) * a.p + (f3 - 2 * f2 + f) * h * a.dp_dd +
                     (-2 * f3 + 3 * f2) * b.p + (f3 - f2) * h * b.dp_dd;
    return {p, a.dp_dd + f * (b.dp_dd - a.dp_dd), a.dp_dsigma + f * (b.dp_dsigma - a.dp_dsigma)};
  }

 private:
  static constexpr double kPerPx = 16.0;
  double reach_ = 0;
  std::vector<EdgeProfileValue> values_;
};

// A line of the pattern in normalised tag coordinates: m . (x^, y^, 1) = 0, > 0 on the side of
// larger x (vertical lines) or y (horizontal lines).
struct TagLine {
  Eigen::Vector3d m;
  bool vertical;
};

// The pattern prepared for fitting: unique lines, rectangles as line indices.
struct Layout {
  std::vector<TagLine> lines;
  struct Rect {
    int x0, x1, y0, y1;  // Line indices.
  };
  std::vector<Rect> rects;
  std::array<int, 4> limits;  // The region's bounding lines x = -m, x = W + m, y = -m, y = W + m.
  std::array<Eigen::Vector2d, 4> region_corners;   // Normalised tag coordinates.
  int middle_vertical = 0, middle_horizontal = 0;  // Lines x = W / 2, y = W / 2 (for the tables).
};

Layout MakeLayout(const TagPattern& pattern) {
  Layout layout;
  const double half = pattern.width_cells / 2.0;
  std::map<std::pair<bool, double>, int> index;
  auto line = [&](bool vertical, double cells) {
    const auto key = std::make_pair(vertical, cells);
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const double c = (cells - half) / half;
    const Eigen::Vector3d m = vertical ? Eigen::Vector3d(1, 0, -c) : Eigen::Vector3d(0, 1, -c);
    layout.lines.push_back({m, vertical});
    index[key] = static_cast<int>(layout.lines.size()) - 1;
    return static_cast<int>(layout.lines.size()) - 1;
  };
  for (const TagPattern::Rect& r : pattern.black) {
    layout.rects.push_back(
        {line(true, r.x0), line(true, r.x1), line(false, r.y0), line(false, r.y1)});
  }
  const double m = pattern.white_margin_cells, w = pattern.width_cells;
  layout.limits = {line(true, -m), line(true, w + m), line(false, -m), line(false, w + m)};
  layout.middle_vertical = line(true, half);
  layout.middle_horizontal = line(false, half);
  const double e = (m + half) / half;
  layout.region_corners = {Eigen::Vector2d(-e, -e), Eigen::Vector2d(e, -e), Eigen::Vector2d(e, e),
                           Eigen::Vector2d(-e, e)};
  return layout;
}

Eigen::Matrix3d HomographyOf(const ParamVector& x) {
  Eigen::Matrix3d g;
  g << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], 1.0;
  return g;
}

// The four corners (normalised pixel coordinates) of G: G c~ ~ q~ for q = (+-1, +-1).
bool CornersOf(const Eigen::Matrix3d& g, std::array<Eigen::Vector2d, 4>* corners) {
  static const std::array<Eigen::Vector2d, 4> kTag = {Eigen::Vector2d(-1, -1),
                                                      Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                                      Eigen::Vector2d(-1, 1)};
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(g);
  if (!lu.isInvertible()) return false;
  const Eigen::Matrix3d inv = lu.inverse();
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d c = inv * kTag[k].homogeneous();
    if (!(std::abs(c.z()) > 1e-12)) return false;
    (*corners)[k] = c.hnormalized();
  }
  return true;
}

// One pixel of the fit.
struct FitPixel {
  Eigen::Vector2d p;  // Normalised pixel coordinates.
  double gray;
  int first_line, num_lines;  // The lines of its near rectangles (pixel_lines_).
  int first_rect, num_rects;  // Its near rectangles as 4 slots of its lines (pixel_rects_).
  int deep;                   // Rectangles that contain it beyond the profile's reach.
};
using RectSlots = std::array<uint8_t, 4>;  // x0, x1, y0, y1 among the pixel's lines.

class TagFit {
 public:
  TagFit(const GrayImageView& image, const TagPattern& pattern, const PhotometricFitOptions& o,
         const CameraIntrinsics* camera)
      : image_(image),
        pattern_(pattern),
        options_(o),
        layout_(MakeLayout(pattern)),
        camera_(camera),
        a_inv_(camera ? Eigen::Matrix3d(camera->Matrix().inverse()) : Eigen::Matrix3d::Identity()) {
  }

  PhotometricFitResult Run(const std::array<Eigen::Vector2d, 4>& initial);

 private:
  // Selects the pixels for parameters x (classification radius from sigma). False with the
  // failure set when the region is unusable.
  bool Classify(const ParamVector& x, PhotometricFitResult* result);
  // Cost, J^T J and J^T r at x; false when x is invalid (a pixel behind the homography's horizon).
  bool Evaluate(const ParamVector& x, double* cost, ParamMatrix* jtj, ParamVector* jtr) const;
  bool InitialHomography(const std::array<Eigen::Vector2d, 4>& corners, ParamVector* x) const;
  // The model plane: pixels themselves, or with a camera the undistorted normalised image plane,
  // where the tag's edges are straight. p^ = (model point - centre_) / scale_.
  bool ModelOf(const Eigen::Vector2d& pixel, Eigen::Vector2d* p_hat) const;
  // d p^ / d pixel at a model point (I / scale_ without a camera).
  Eigen::Matrix2d ModelJacobian(const Eigen::Vector2d& p_hat) const;
  Eigen::Vector2d ToPixel(const Eigen::Vector2d& p_hat) const;
  // Pixels per unit of p^ at the tag's centre (for the step and re-classification thresholds).
  double PixelsPerUnit() const { return px_per_unit_; }

  const GrayImageView& image_;
  const TagPattern& pattern_;
  const PhotometricFitOptions& options_;
  const Layout layout_;
  const CameraIntrinsics* camera_;  // Null: a pinhole tag, straight edges in the image.
  const Eigen::Matrix3d a_inv_;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double scale_ = 1, px_per_unit_ = 1;
  Eigen::Matrix2d centre_jacobian_ = Eigen::Matrix2d::Identity();  // ModelJacobian(0).
  std::vector<FitPixel> pixels_;
  std::vector<Eigen::Matrix2d> pixel_jacobians_;  // With a camera: ModelJacobian per pixel.
  std::vector<int> pixel_lines_;
  std::vector<RectSlots> pixel_rects_;
  std::array<Eigen::Vector2d, 4> classified_corners_;
  double classified_sigma_ = 0;
};

bool TagFit::ModelOf(const Eigen::Vector2d& pixel, Eigen::Vector2d* p_hat) const {
  if (!camera_) {
    *p_hat = (pixel - centre_) / scale_;
    return true;
  }
  Eigen::Vector2d undistorted;
  if (!UndistortNormalized(*camera_, (a_inv_ * pixel.homogeneous()).hnormalized(), &undistorted))
    return false;
  *p_hat = (undistorted - centre_) / scale_;
  return true;
}

Eigen::Vector2d TagFit::ToPixel(const Eigen::Vector2d& p_hat) const {
  if (!camera_) return centre_ + scale_ * p_hat;
  Eigen::Vector2d pixel(std::numeric_limits<double>::quiet_NaN(), 0);
  ProjectPoint(*camera_, (centre_ + scale_ * p_hat).homogeneous(), &pixel);
  return pixel;
}

Eigen::Matrix2d TagFit::ModelJacobian(const Eigen::Vector2d& p_hat) const {
  if (!camera_) return Eigen::Matrix2d::Identity() / scale_;
  // d pixel / d p^ by central differences of the projection (smooth, no iteration), inverted.
  constexpr double h = 1e-6;
  Eigen::Matrix2d forward;
  for (int a = 0; a < 2; ++a) {
    const Eigen::Vector2d e = Eigen::Vector2d::Unit(a) * h;
    forward.col(a) = (ToPixel(p_hat + e) - ToPixel(p_hat - e)) / (2 * h);
  }
  return forward.inverse();
}

bool TagFit::InitialHomography(const std::array<Eigen::Vector2d, 4>& corners,
                               ParamVector* x) const {
  // Normalised pixel corner k -> tag corner (+-1, +-1): 8 equations in G's 8 free entries.
  static const std::array<Eigen::Vector2d, 4> kTag = {Eigen::Vector2d(-1, -1),
                                                      Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                                      Eigen::Vector2d(-1, 1)};
  Eigen::Matrix<double, 8, 8> a;
  Eigen::Matrix<double, 8, 1> b;
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector2d p;
    if (!ModelOf(corners[k], &p)) return false;
    const double u = kTag[k].x(), v = kTag[k].y();
    a.row(2 * k) << p.x(), p.y(), 1, 0, 0, 0, -u * p.x(), -u * p.y();
    a.row(2 * k + 1) << 0, 0, 0, p.x(), p.y(), 1, -v * p.x(), -v * p.y();
    b[2 * k] = u;
    b[2 * k + 1] = v;
  }
  const Eigen::FullPivLU<Eigen::Matrix<double, 8, 8>> lu(a);
  if (!lu.isInvertible()) return false;
  x->head<8>() = lu.solve(b);
  return x->head<8>().allFinite();
}

bool TagFit::Classify(const ParamVector& x, PhotometricFitResult* result) {
  pixels_.clear();
  pixel_lines_.clear();
  pixel_rects_.clear();
  pixel_jacobians_.clear();
  const Eigen::Matrix3d g = HomographyOf(x);
  const double reach = ProfileReachPx(x[kSigma]);
  // Margin: corners may move kReclassifyPx before the pixels are classified again.
  const double near_px = reach + kReclassifyPx;
  const double include_px = near_px;  // Flat pixels up to the re-classification margin.
  std::vector<Eigen::Vector3d> lines(layout_.lines.size()), raw_lines(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    const Eigen::Vector3d l = g.transpose() * layout_.lines[i].m;
    const double n = l.head<2>().norm();
    if (!(n > 0)) {
      result->failure = FitFailure::kDiverged;
      result->message = "degenerate homography";
      return false;
    }
    raw_lines[i] = l;
    lines[i] = scale_ * l / n;  // Without a camera: f(p) = lines[i] . p^~ in px.
  }
  // The region's image quadrilateral, its bounding box.
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(g);
  if (!lu.isInvertible()) {
    result->failure = FitFailure::kDiverged;
    result->message = "degenerate homography";
    return false;
  }
  const Eigen::Matrix3d inv = lu.inverse();
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  // With a camera the region's sides bend in the image: 8 points a side, and a margin.
  const int samples = camera_ ? 8 : 1;
  for (int k = 0; k < 4; ++k) {
    for (int s = 0; s < samples; ++s) {
      const Eigen::Vector2d q = layout_.region_corners[k] +
                                (layout_.region_corners[(k + 1) % 4] - layout_.region_corners[k]) *
                                    (static_cast<double>(s) / samples);
      const Eigen::Vector3d h = inv * q.homogeneous();
      if (!(h.z() * (inv * Eigen::Vector3d(0, 0, 1)).z() > 0)) {
        result->failure = FitFailure::kDiverged;
        result->message = "the tag's region crosses the homography's horizon";
        return false;
      }
      const Eigen::Vector2d p = ToPixel(h.hnormalized());
      u0 = std::min(u0, p.x()), u1 = std::max(u1, p.x());
      v0 = std::min(v0, p.y()), v1 = std::max(v1, p.y());
    }
  }
  if (camera_) u0 -= 2, v0 -= 2, u1 += 2, v1 += 2;
  constexpr double kMaxRegionPx = 4096;
  if (!(u1 - u0 < kMaxRegionPx && v1 - v0 < kMaxRegionPx)) {
    result->failure = FitFailure::kDiverged;
    result->message = "the tag's region is larger than 4096 px";
    return false;
  }
  long inside = 0, outside = 0;
  const int i0 = static_cast<int>(std::floor(u0)), i1 = static_cast<int>(std::ceil(u1));
  const int j0 = static_cast<int>(std::floor(v0)), j1 = static_cast<int>(std::ceil(v1));
  const std::array<double, 4> limit_sign = {1, -1, 1, -1};
  std::vector<double> line_values(lines.size());
  for (int j = j0; j <= j1; ++j) {
    // The row's span inside the region: each limit line is linear in i along the row.
    double lo = i0, hi = i1;
    const double y = (j - centre_.y()) / scale_;
    for (int k = 0; k < 4 && !camera_; ++k) {
      const Eigen::Vector3d& l = lines[layout_.limits[k]];
      // limit_sign * (l.x (i - cx) / S + l.y y + l.z) > reach.
      const double slope = limit_sign[k] * l.x() / scale_;
      const double offset =
          limit_sign[k] * (l.y() * y + l.z() - l.x() * centre_.x() / scale_) - reach;
      if (std::abs(slope) < 1e-12) {
        if (offset <= 0) hi = lo - 1;
      } else if (slope > 0) {
        lo = std::max(lo, -offset / slope);
      } else {
        hi = std::min(hi, -offset / slope);
      }
    }
    const int row_lo = static_cast<int>(std::floor(lo)), row_hi = static_cast<int>(std::ceil(hi));
    for (int i = std::max(i0, row_lo); i <= std::min(i1, row_hi); ++i) {
      Eigen::Vector3d p((i - centre_.x()) / scale_, (j - centre_.y()) / scale_, 1);
      Eigen::Matrix2d m = Eigen::Matrix2d::Identity() / scale_;
      if (camera_) {
        Eigen::Vector2d p_hat;
        if (!ModelOf(Eigen::Vector2d(i, j), &p_hat)) continue;
        p = p_hat.homogeneous();
        m = ModelJacobian(p_hat);
      }
      // Signed distance (px) to line l: (l . p^~) / |M^T l_xy| (the model's gradient in pixels).
      auto distance = [&](size_t l) {
        return camera_ ? raw_lines[l].dot(p) / (m.transpose() * raw_lines[l].head<2>()).norm()
                       : lines[l].dot(p);
      };
      bool in_region = true;
      for (int k = 0; k < 4 && in_region; ++k) {
        in_region = limit_sign[k] * distance(layout_.limits[k]) > reach;
      }
      if (!in_region) continue;
      if (i < 0 || j < 0 || i >= image_.width || j >= image_.height) {
        ++outside;
        continue;
      }
      ++inside;
      FitPixel px{p.head<2>(),
                  static_cast<double>(image_.at(i, j)),
                  static_cast<int>(pixel_lines_.size()),
                  0,
                  static_cast<int>(pixel_rects_.size()),
                  0,
                  0};
      auto slot = [&](int line) {
        for (int k = 0; k < px.num_lines; ++k) {
          if (pixel_lines_[px.first_line + k] == line) return static_cast<uint8_t>(k);
        }
        pixel_lines_.push_back(line);
        return static_cast<uint8_t>(px.num_lines++);
      };
      bool include = false;
      for (size_t l = 0; l < lines.size(); ++l) line_values[l] = distance(l);
      for (size_t r = 0; r < layout_.rects.size(); ++r) {
        const Layout::Rect& rect = layout_.rects[r];
        const double inside_min = std::min({line_values[rect.x0], -line_values[rect.x1],
                                            line_values[rect.y0], -line_values[rect.y1]});
        include |= inside_min > -include_px && inside_min < include_px;
        if (inside_min >= near_px) {
          ++px.deep;
        } else if (inside_min > -near_px && px.num_lines <= kMaxLinesPerPixel - 4) {
          pixel_rects_.push_back({slot(rect.x0), slot(rect.x1), slot(rect.y0), slot(rect.y1)});
          ++px.num_rects;
        }
      }
      if (include) {
        pixels_.push_back(px);
        if (camera_) pixel_jacobians_.push_back(m);
      } else {
        pixel_lines_.resize(px.first_line);
        pixel_rects_.resize(px.first_rect);
      }
    }
  }
  if (outside > options_.max_outside_fraction * static_cast<double>(inside + outside)) {
    result->failure = FitFailure::kImageBorder;
    result->message = "the tag's region is cut by the image border (" + std::to_string(outside) +
                      " of " + std::to_string(inside + outside) + " px outside)";
    return false;
  }
  if (static_cast<int>(pixels_.size()) < options_.min_pixels) {
    result->failure = FitFailure::kTooFewPixels;
    result->message = "the tag's region has " + std::to_string(pixels_.size()) +
                      " usable pixels (min_pixels " + std::to_string(options_.min_pixels) + ")";
    return false;
  }
  CornersOf(g, &classified_corners_);
  classified_sigma_ = x[kSigma];
  return true;
}

bool TagFit::Evaluate(const ParamVector& x, double* cost, ParamMatrix* jtj,
                      ParamVector* jtr) const {
  const Eigen::Matrix3d g = HomographyOf(x);
  const double sigma = std::max(x[kSigma], kMinSigmaPx);
  const double black = x[kBlack], white = x[kWhite], contrast = black - white;
  const Eigen::Vector2d shading(x[kShadeX], x[kShadeY]);
  const size_t num_lines = layout_.lines.size();
  // Per line: f(p) = S (l . p^) / |l_xy| = unit . p^ (px) and d f / d l = S (p^ - (l^ . p^) l^_xy0)
  // / |l_xy|, with l = G^T m linear in G.
  std::vector<Eigen::Vector3d> unit(num_lines), raw(num_lines);
  std::vector<double> inv_norm(num_lines);
  for (size_t i = 0; i < num_lines; ++i) {
    const Eigen::Vector3d l = g.transpose() * layout_.lines[i].m;
    const double n = l.head<2>().norm();
    if (!(n > 1e-12)) return false;
    raw[i] = l;
    unit[i] = l / n;
    inv_norm[i] = 1 / n;
  }
  // The edges' normals in the image (with a camera: at the tag's centre) for the pixel box.
  auto image_normal = [&](int line) -> Eigen::Vector2d {
    return (centre_jacobian_.transpose() * raw[line].head<2>()).normalized();
  };
  ProfileTable vertical, horizontal;
  vertical.Build(sigma, image_normal(layout_.middle_vertical));
  horizontal.Build(sigma, image_normal(layout_.middle_horizontal));

  jtj->setZero();
  jtr->setZero();
  *cost = 0;
  // Per pixel, per line of its rectangles: P (f), P' (f), dP/dsigma (f), and d b / d f. The profile
  // is odd about one half: the far edge of a rectangle contributes 1 - P(f), so that
  // [P(d_0) + P(d_1) - 1] = P(f_0) - P(f_1) with f the signed distance towards larger x (or y).
  std::array<EdgeProfileValue, kMaxLinesPerPixel> profile;
  std::array<double, kMaxLinesPerPixel> weight;
  // With a camera, per line: 1 / N and M M^T l_xy / N^2, N = |M^T l_xy| (f = l . p^~ / N).
  std::array<double, kMaxLinesPerPixel> lens_inv_n;
  std::array<Eigen::Vector2d, kMaxLinesPerPixel> lens_q;
  Eigen::Matrix<double, kNumParams, 1> jac;
  for (size_t index = 0; index < pixels_.size(); ++index) {
    const FitPixel& px = pixels_[index];
    const Eigen::Vector3d p(px.p.x(), px.p.y(), 1);
    if (!((g.row(2) * p)(0) > 0)) return false;  // Behind the homography's horizon.
    std::fill(weight.begin(), weight.begin() + px.num_lines, 0.0);
    const int* lines_of_pixel = pixel_lines_.data() + px.first_line;
    for (int k = 0; k < px.num_lines; ++k) {
      const int line = lines_of_pixel[k];
      double f;
      if (camera_) {
        const Eigen::Matrix2d& m = pixel_jacobians_[index];
        const Eigen::Vector2d mt_l = m.transpose() * raw[line].head<2>();
        lens_inv_n[k] = 1 / mt_l.norm();
        lens_q[k] = m * mt_l * (lens_inv_n[k] * lens_inv_n[k]);
        f = raw[line].dot(p) * lens_inv_n[k];
      } else {
        f = scale_ * unit[line].dot(p);
      }
      profile[k] = layout_.lines[line].vertical ? vertical(f) : horizontal(f);
    }
    double b = px.deep, db_dsigma = 0;
    for (int k = 0; k < px.num_rects; ++k) {
      const RectSlots& r = pixel_rects_[px.first_rect + k];
      const EdgeProfileValue &a0 = profile[r[0]], &a1 = profile[r[1]];
      const EdgeProfileValue &c0 = profile[r[2]], &c1 = profile[r[3]];
      const double fx = a0.p - a1.p, fy = c0.p - c1.p;
      b += fx * fy;
      db_dsigma += (a0.dp_dsigma - a1.dp_dsigma) * fy + (c0.dp_dsigma - c1.dp_dsigma) * fx;
      weight[r[0]] += a0.dp_dd * fy;
      weight[r[1]] -= a1.dp_dd * fy;
      weight[r[2]] += c0.dp_dd * fx;
      weight[r[3]] -= c1.dp_dd * fx;
    }
    const double base = white + contrast * b;
    const double shade = 1 + shading.dot(px.p);
    double model = shade * base;
    jac.setZero();
    bool censored = false;
    if (model >= 255 || model <= 0) {
      // Saturated: the sensor clips; an equally clipped pixel carries no information.
      censored = (model >= 255 && px.gray >= 255) || (model <= 0 && px.gray <= 0);
      model = std::clamp(model, 0.0, 255.0);
    } else {
      // d model / d G_ij = sum over lines of w m_i (d f / d l_j); m = (1, 0, m_2) for vertical
      // lines and (0, 1, m_2) for horizontal ones.
      Eigen::Matrix3d dg = Eigen::Matrix3d::Zero();
      for (int k = 0; k < px.num_lines; ++k) {
        const int line = lines_of_pixel[k];
        Eigen::Vector3d df;  // weight * d f / d l.
        if (camera_) {
          const double w = lens_inv_n[k] * weight[k], f = raw[line].dot(p) * lens_inv_n[k];
          df = Eigen::Vector3d(w * (p.x() - f * lens_q[k].x() / lens_inv_n[k]),
                               w * (p.y() - f * lens_q[k].y() / lens_inv_n[k]), w);
        } else {
          const Eigen::Vector3d& u = unit[line];
          const double w = scale_ * inv_norm[line] * weight[k], f = u.dot(p);
          df = Eigen::Vector3d(w * (p.x() - f * u.x()), w * (p.y() - f * u.y()), w);
        }
        const TagLine& tag_line = layout_.lines[line];
        dg.row(tag_line.vertical ? 0 : 1) += df;
        dg.row(2) += tag_line.m.z() * df;
      }
      dg *= shade * contrast;
      jac << dg(0, 0), dg(0, 1), dg(0, 2), dg(1, 0), dg(1, 1), dg(1, 2), dg(2, 0), dg(2, 1),
          shade * contrast * db_dsigma, shade * b, shade * (1 - b), base * px.p.x(),
          base * px.p.y();
      if (!options_.fit_shading) jac[kShadeX] = jac[kShadeY] = 0;
    }
    if (censored) continue;
    const double r = px.gray - model;
    *cost += r * r;
    double* h = jtj->data();  // Column-major: the upper triangle is (row <= col).
    // A pixel beyond every edge's reach depends only on the levels and the shading.
    const int first = px.num_rects == 0 ? kBlack : 0;
    for (int col = first; col < kNumParams; ++col) {
      const double jc = jac[col];
      for (int row = first; row <= col; ++row) h[col * kNumParams + row] += jac[row] * jc;
    }
    for (int i = first; i < kNumParams; ++i) (*jtr)[i] += jac[i] * r;
  }
  *jtj = jtj->selfadjointView<Eigen::Upper>();
  return true;
}

PhotometricFitResult TagFit::Run(const std::array<Eigen::Vector2d, 4>& initial) {
  PhotometricFitResult result;
  result.corners = initial;
  // The model plane's corners: the pixels, or their undistorted normalised coordinates.
  std::array<Eigen::Vector2d, 4> model_corners = initial;
  for (int k = 0; k < 4 && camera_; ++k) {
    if (!UndistortNormalized(*camera_, (a_inv_ * initial[k].homogeneous()).hnormalized(),
                             &model_corners[k])) {
      result.failure = FitFailure::kDiverged;
      result.message = "corner " + std::to_string(k) + " is outside the camera's valid region";
      return result;
    }
  }
  centre_.setZero();
  double perimeter = 0, pixel_perimeter = 0;
  for (int k = 0; k < 4; ++k) {
    centre_ += model_corners[k] / 4;
    perimeter += (model_corners[(k + 1) % 4] - model_corners[k]).norm();
    pixel_perimeter += (initial[(k + 1) % 4] - initial[k]).norm();
  }
  scale_ = perimeter / 8;  // Half the mean edge length.
  centre_jacobian_ = ModelJacobian(Eigen::Vector2d::Zero());
  px_per_unit_ = 1 / std::sqrt(std::abs(centre_jacobian_.determinant()));
  ParamVector x = ParamVector::Zero();
  if (!(pixel_perimeter > 8) || !(scale_ > 0) || !centre_jacobian_.allFinite() ||
      !InitialHomography(initial, &x)) {
    result.failure = FitFailure::kDiverged;
    result.message = "the detector's corners do not span a quadrilateral";
    return result;
  }
  x[kSigma] = options_.initial_blur_px;
  if (!Classify(x, &result)) return result;
  // Levels: the medians of the pixels deep in black and of those far from every black rectangle.
  std::vector<double> dark, bright, all;
  for (const FitPixel& px : pixels_) {
    all.push_back(px.gray);
    if (px.num_rects == 0) (px.deep > 0 ? dark : bright).push_back(px.gray);
  }
  auto quantile = [](std::vector<double> v, double q) {
    const size_t k = static_cast<size_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
    return v[k];
  };
  x[kBlack] = dark.size() >= 8 ? quantile(dark, 0.5) : quantile(all, 0.05);
  x[kWhite] = bright.size() >= 8 ? quantile(bright, 0.5) : quantile(all, 0.95);
  if (!(x[kWhite] - x[kBlack] >= options_.min_contrast_gray)) {
    result.failure = FitFailure::kLowContrast;
    result.message = "the tag's region has a contrast of " + std::to_string(x[kWhite] - x[kBlack]) +
                     " gray levels (min_contrast_gray " +
                     std::to_string(options_.min_contrast_gray) + ")";
    return result;
  }

  double cost = 0;
  ParamMatrix jtj;
  ParamVector jtr;
  if (!Evaluate(x, &cost, &jtj, &jtr)) {
    result.failure = FitFailure::kDiverged;
    result.message = "the initial homography is invalid over the tag's region";
    return result;
  }
  double lambda = 1e-4;
  bool converged = false;
  std::array<Eigen::Vector2d, 4> corners;
  CornersOf(HomographyOf(x), &corners);
  int it = 0;
  for (; it < options_.max_iterations && !converged; ++it) {
    ParamMatrix a = jtj;
    for (int i = 0; i < kNumParams; ++i) a(i, i) = a(i, i) * (1 + lambda) + 1e-12;
    if (!options_.fit_shading) {
      for (int i : {kShadeX, kShadeY}) a(i, i) = 1;
    }
    const ParamVector step = a.ldlt().solve(jtr);
    ParamVector trial = x + step;
    trial[kSigma] = std::max(trial[kSigma], kMinSigmaPx);
    double trial_cost = 0;
    ParamMatrix trial_jtj;
    ParamVector trial_jtr;
    std::array<Eigen::Vector2d, 4> trial_corners;
    // A step is tried only while every corner stays near the detector's: farther, the region
    // (and the cost of one evaluation) would grow without bound.
    bool valid = step.allFinite() && trial[kSigma] <= options_.max_blur_px &&
                 CornersOf(HomographyOf(trial), &trial_corners);
    double moved = 0, since_classified = 0;
    for (int k = 0; k < 4 && valid; ++k) {
      const Eigen::Vector2d c = ToPixel(trial_corners[k]);
      valid = (c - initial[k]).norm() <= 2 * options_.max_correction_px;
      moved = std::max(moved, px_per_unit_ * (trial_corners[k] - corners[k]).norm());
      since_classified = std::max(
          since_classified, px_per_unit_ * (trial_corners[k] - classified_corners_[k]).norm());
    }
    const bool sigma_settled = std::abs(trial[kSigma] - x[kSigma]) < 1e-3;
    if (valid && moved < options_.convergence_px && sigma_settled && lambda < 1e-2) {
      // Gauss-Newton's next step is below the tolerance: x is the minimum to within it (the
      // information J^T J and the cost at x are those of the solution).
      converged = true;
      break;
    }
    if (!valid || !Evaluate(trial, &trial_cost, &trial_jtj, &trial_jtr) || !(trial_cost < cost)) {
      // At the minimum, steps below the tolerance may no longer lower the cost in floating point.
      converged = valid && moved < options_.convergence_px && sigma_settled;
      lambda *= 10;
      if (lambda > 1e8) break;
      continue;
    }
    x = trial;
    corners = trial_corners;
    cost = trial_cost;
    jtj = trial_jtj;
    jtr = trial_jtr;
    lambda = std::max(lambda / 10, 1e-9);
    converged = moved < options_.convergence_px && sigma_settled;
    if (since_classified > kReclassifyPx ||
        x[kSigma] > classified_sigma_ +
                        kReclassifySigmaPx) {  // The pixels' rectangle lists may be stale: rebuild.
      if (!Classify(x, &result)) return result;
      if (!Evaluate(x, &cost, &jtj, &jtr)) break;
      converged = false;
    }
  }
  result.iterations = it;
  if (!converged) {
    result.failure =
        it >= options_.max_iterations ? FitFailure::kNotConverged : FitFailure::kDiverged;
    result.message =
        it >= options_.max_iterations
            ? "not converged in " + std::to_string(options_.max_iterations) + " iterations"
            : "no step lowers the cost";
    return result;
  }
  // A PSF wider than the one the pixels were classified with reaches farther: classify again.
  if (x[kSigma] > classified_sigma_ + kReclassifySigmaPx &&
      (!Classify(x, &result) || !Evaluate(x, &cost, &jtj, &jtr))) {
    if (result.ok()) result.failure = FitFailure::kDiverged;
    return result;
  }
  result.pixels = static_cast<int>(pixels_.size());
  result.blur_px = x[kSigma];
  result.black_gray = x[kBlack];
  result.white_gray = x[kWhite];
  const double dof = std::max(1.0, static_cast<double>(pixels_.size()) - kNumParams);
  result.residual_rms_gray = std::sqrt(cost / dof);
  const double contrast = x[kWhite] - x[kBlack];
  if (!(contrast >= options_.min_contrast_gray) ||
      !(contrast >= options_.min_contrast_to_residual * result.residual_rms_gray)) {
    result.failure = FitFailure::kLowContrast;
    result.message = "fitted contrast " + std::to_string(contrast) + " gray levels against a " +
                     std::to_string(result.residual_rms_gray) +
                     " gray-level residual RMS (min_contrast_gray " +
                     std::to_string(options_.min_contrast_gray) + ", min_contrast_to_residual " +
                     std::to_string(options_.min_contrast_to_residual) + ")";
    return result;
  }
  std::array<Eigen::Vector2d, 4> pixel_corners;
  for (int k = 0; k < 4; ++k) {
    pixel_corners[k] = ToPixel(corners[k]);
    if (!((pixel_corners[k] - initial[k]).norm() <= options_.max_correction_px)) {
      result.failure = FitFailure::kMoved;
      result.message = "corner " + std::to_string(k) + " moved " +
                       std::to_string((pixel_corners[k] - initial[k]).norm()) +
                       " px from the detector's (max_correction_px " +
                       std::to_string(options_.max_correction_px) + ")";
      return result;
    }
  }
  // Cramer-Rao: cov(x) = sigma_n^2 (J^T J)^-1; corner k's derivative in G by the implicit
  // function theorem on pi(G c~) = q_k: dc / dG_ij = -A^-1 Jpi[:, i] c~_j, A = Jpi G[:, 0:2].
  ParamMatrix info = jtj;
  if (!options_.fit_shading) {
    for (int i : {kShadeX, kShadeY}) {
      info.row(i).setZero();
      info.col(i).setZero();
      info(i, i) = 1;
    }
  }
  const ParamMatrix covariance = (cost / dof) * info.ldlt().solve(ParamMatrix::Identity());
  const Eigen::Matrix3d g = HomographyOf(x);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d c = corners[k].homogeneous();
    const Eigen::Vector3d h = g * c;
    Eigen::Matrix<double, 2, 3> jpi;
    jpi << 1 / h.z(), 0, -h.x() / (h.z() * h.z()), 0, 1 / h.z(), -h.y() / (h.z() * h.z());
    const Eigen::Matrix2d a_inv = (jpi * g.leftCols<2>()).inverse();
    const Eigen::Matrix2d to_pixel = ModelJacobian(corners[k]).inverse();  // d pixel / d p^.
    Eigen::Matrix<double, 2, 8> d;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (i == 2 && j == 2) continue;
        d.col(3 * i + j) = -to_pixel * a_inv * jpi.col(i) * c[j];
      }
    }
    result.corner_covariance_px2[k] = d * covariance.topLeftCorner<8, 8>() * d.transpose();
    result.crlb_px[k] = std::sqrt(std::max(0.0, result.corner_covariance_px2[k].trace() / 2));
  }
  result.corners = pixel_corners;
  return result;
}

}  // namespace

EdgeProfileValue EdgeProfile(double d, double sigma, double nx, double ny) {
  sigma = std::max(sigma, 1e-3);
  double a = std::abs(nx), b = std::abs(ny);
  if (a < b) std::swap(a, b);
  // Q2 (x) and its derivatives: Q2' = Q1 = x Phi + sigma phi, Q1' = Phi; dQ2/dsigma = sigma Phi,
  // dQ1/dsigma = phi.
  struct Terms {
    double q2, q1, phi, density;
  };
  auto terms = [sigma](double x) {
    const double u = x / sigma, cdf = Phi(u), pdf = PhiDensity(u);
    return Terms{0.5 * (x * x + sigma * sigma) * cdf + 0.5 * x * sigma * pdf, x * cdf + sigma * pdf,
                 cdf, pdf};
  };
  if (b < 1e-4) {  // One box of width a: P = [Q1(d + a/2) - Q1(d - a/2)] / a.
    const Terms hi = terms(d + a / 2), lo = terms(d - a / 2);
    return {(hi.q1 - lo.q1) / a, (hi.phi - lo.phi) / a, (hi.density - lo.density) / a};
  }
  const Terms t1 = terms(d + (a + b) / 2), t2 = terms(d + (a - b) / 2), t3 = terms(d - (a - b) / 2),
              t4 = terms(d - (a + b) / 2);
  const double inv = 1 / (a * b);
  return {(t1.q2 - t2.q2 - t3.q2 + t4.q2) * inv, (t1.q1 - t2.q1 - t3.q1 + t4.q1) * inv,
          sigma * (t1.phi - t2.phi - t3.phi + t4.phi) * inv};
}

bool TagPattern::FromFamily(const TagFamily& family, int id, double white_margin_cells,
                            double corner_square_cells, TagPattern* pattern, std::string* why) {
  if (id < 0 || id >= family.num_codes()) {
    if (why) *why = "tag id " + std::to_string(id) + " is not in " + family.name();
    return false;
  }
  if (!(white_margin_cells > 0) || !(corner_square_cells >= 0)) {
    if (why) *why = "white_margin_cells must be > 0 and corner_square_cells >= 0";
    return false;
  }
  TagPattern p;
  const int w = family.width_at_border(), start = family.border_start();
  p.width_cells = w;
  p.white_margin_cells = white_margin_cells;
  // Row runs of black cells, merged downward into maximal rectangles while a run repeats.
  std::map<std::pair<int, int>, TagPattern::Rect> open;
  for (int row = 0; row < w; ++row) {
    std::map<std::pair<int, int>, TagPattern::Rect> next;
    const double y1 = w - row, y0 = y1 - 1;  // Bitmap row 0 is the top: y grows upward.
    for (int col = 0; col < w;) {
      if (family.IsWhite(id, start + col, start + row)) {
        ++col;
        continue;
      }
      int end = col;
      while (end < w && !family.IsWhite(id, start + end, start + row)) ++end;
      const auto key = std::make_pair(col, end);
      auto it = open.find(key);
      if (it != open.end()) {
        TagPattern::Rect r = it->second;
        r.y0 = y0;
        next[key] = r;
        open.erase(it);
      } else {
        next[key] = {static_cast<double>(col), y0, static_cast<double>(end), y1};
      }
      col = end;
    }
    for (const auto& kv : open) p.black.push_back(kv.second);
    open = std::move(next);
  }
  for (const auto& kv : open) p.black.push_back(kv.second);
  if (corner_square_cells > 0) {
    const double s = corner_square_cells;
    p.black.push_back({-s, -s, 0, 0});
    p.black.push_back({static_cast<double>(w), -s, w + s, 0});
    p.black.push_back({static_cast<double>(w), static_cast<double>(w), w + s, w + s});
    p.black.push_back({-s, static_cast<double>(w), 0, w + s});
  }
  *pattern = std::move(p);
  return true;
}

bool PhotometricFitOptions::Check(std::string* why) const {
  std::string msg;
  if (max_iterations < 1) msg = "max_iterations must be >= 1";
  if (!(max_blur_px > 0 && max_blur_px <= 20)) msg = "max_blur_px must lie in (0, 20]";
  if (!(initial_blur_px > 0 && initial_blur_px < max_blur_px))
    msg = "initial_blur_px must lie in (0, max_blur_px)";
  if (!(max_correction_px > 0)) msg = "max_correction_px must be > 0";
  if (!(min_contrast_gray > 0)) msg = "min_contrast_gray must be > 0";
  if (!(min_contrast_to_residual >= 0)) msg = "min_contrast_to_residual must be >= 0";
  if (!(convergence_px > 0)) msg = "convergence_px must be > 0";
  if (min_pixels < kNumParams + 1) msg = "min_pixels must be > 13";
  if (!(max_outside_fraction >= 0 && max_outside_fraction < 1))
    msg = "max_outside_fraction must lie in [0, 1)";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

const char* FitFailureName(FitFailure failure) {
  switch (failure) {
    case FitFailure::kNone:
      return "none";
    case FitFailure::kImageBorder:
      return "image_border";
    case FitFailure::kLowContrast:
      return "low_contrast";
    case FitFailure::kTooFewPixels:
      return "too_few_pixels";
    case FitFailure::kDiverged:
      return "diverged";
    case FitFailure::kNotConverged:
      return "not_converged";
    case FitFailure::kMoved:
      return "moved";
  }
  return "unknown";
}

PhotometricFitResult FitTagPhotometric(const GrayImageView& image, const TagPattern& pattern,
                                       const std::array<Eigen::Vector2d, 4>& initial_corners,
                                       const PhotometricFitOptions& options,
                                       const CameraIntrinsics* camera) {
  PhotometricFitResult result;
  result.corners = initial_corners;
  if (!options.Check(&result.message)) {
    result.failure = FitFailure::kDiverged;
    return result;
  }
  if (pattern.black.empty() || pattern.width_cells < 1) {
    result.failure = FitFailure::kDiverged;
    result.message = "the tag pattern has no black";
    return result;
  }
  if (camera && !camera->Check(&result.message)) {
    result.failure = FitFailure::kDiverged;
    return result;
  }
  TagFit fit(image, pattern, options, camera && camera->IsDistorted() ? camera : nullptr);
  return fit.Run(initial_corners);
}

}  // namespace calibench
