// The photometric fit's pixel work (tag_fit.h): the tag's region in the image, the pixels
// classified by the lines within reach of them, and the model's cost, J^T J and J^T r over them.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "detect/tag_fit.h"

namespace calibench {
namespace photometric_internal {

namespace {

// The part of row j within kOutlineMarginPx of a closed `outline` (every pixel of the region is
// inside it): the x extent of the outline's segments clipped to |y - j| <= margin; *lo > *hi when
// the row misses it.
void OutlineRowSpan(const std::vector<Eigen::Vector2d>& outline, int j, double* lo, double* hi) {
  *lo = 1e300, *hi = -1e300;
  for (size_t e = 0; e < outline.size(); ++e) {
    const Eigen::Vector2d& a = outline[e];
    const Eigen::Vector2d& b = outline[(e + 1) % outline.size()];
    const double ya = a.y() - j, yb = b.y() - j;
    if (std::min(ya, yb) > kOutlineMarginPx || std::max(ya, yb) < -kOutlineMarginPx) continue;
    double t0 = 0, t1 = 1;
    if (ya != yb) {
      const double ta = (-kOutlineMarginPx - ya) / (yb - ya);
      const double tb = (kOutlineMarginPx - ya) / (yb - ya);
      t0 = std::max(0.0, std::min(ta, tb)), t1 = std::min(1.0, std::max(ta, tb));
    }
    for (const double t : {t0, t1}) {
      const double xt = a.x() + t * (b.x() - a.x());
      *lo = std::min(*lo, xt - kOutlineMarginPx), *hi = std::max(*hi, xt + kOutlineMarginPx);
    }
  }
}

}  // namespace

bool TagFit::RegionInImage(const Eigen::Matrix3d& g, RegionBox* box,
                           PhotometricFitResult* result) const {
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(g);
  if (!lu.isInvertible()) {
    result->failure = FitFailure::kDiverged;
    result->message = "degenerate homography";
    return false;
  }
  const Eigen::Matrix3d inv = lu.inverse();
  box->u0 = box->v0 = 1e300;
  box->u1 = box->v1 = -1e300;
  double &u0 = box->u0, &u1 = box->u1, &v0 = box->v0, &v1 = box->v1;
  // With a camera the region's sides bend in the image: 8 points a side, and a margin.
  const int samples = camera_ ? 8 : 1;
  std::vector<Eigen::Vector2d>& outline = box->outline;
  outline.clear();
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
      if (camera_) outline.push_back(p);
      u0 = std::min(u0, p.x()), u1 = std::max(u1, p.x());
      v0 = std::min(v0, p.y()), v1 = std::max(v1, p.y());
    }
  }
  if (camera_) {
    u0 -= kOutlineMarginPx, v0 -= kOutlineMarginPx, u1 += kOutlineMarginPx, v1 += kOutlineMarginPx;
  }
  constexpr double kMaxRegionPx = 4096;
  if (!(u1 - u0 < kMaxRegionPx && v1 - v0 < kMaxRegionPx)) {
    result->failure = FitFailure::kDiverged;
    result->message = "the tag's region is larger than 4096 px";
    return false;
  }
  return true;
}

namespace {
// Per limit k of the region: the side of its line where the region lies.
constexpr std::array<double, 4> kLimitSign = {1, -1, 1, -1};
}  // namespace

void TagFit::RowSpan(int j, const RegionBox& region, bool outline_spans, const PatternLines& lines,
                     double reach, double* lo, double* hi) const {
  if (outline_spans) {
    double span_lo = 0, span_hi = 0;
    OutlineRowSpan(region.outline, j, &span_lo, &span_hi);
    *lo = std::max(*lo, span_lo), *hi = std::min(*hi, span_hi);
  }
  if (camera_) return;
  const double y = (j - centre_.y()) / scale_;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& l = lines.scaled[layout_.limits[k]];
    // kLimitSign * (l.x (i - cx) / S + l.y y + l.z) > reach.
    const double slope = kLimitSign[k] * l.x() / scale_;
    const double offset =
        kLimitSign[k] * (l.y() * y + l.z() - l.x() * centre_.x() / scale_) - reach;
    if (std::abs(slope) < 1e-12) {
      if (offset <= 0) *hi = *lo - 1;
    } else if (slope > 0) {
      *lo = std::max(*lo, -offset / slope);
    } else {
      *hi = std::min(*hi, -offset / slope);
    }
  }
}

void TagFit::AddPixel(const PixelAt& at, const PatternLines& lines, const ClassifyMargins& margins,
                      std::vector<double>* line_values) {
  std::vector<double>& values = *line_values;
  FitPixel px{at.p.head<2>(),
              static_cast<double>(image_.at(at.i, at.j)),
              static_cast<int>(pixel_lines_.size()),
              0,
              static_cast<int>(pixel_rects_.size()),
              0,
              0,
              static_cast<long>(at.j) * image_.width + at.i};
  auto slot = [&](int line) {
    // A line farther than the margin keeps its profile's constant until reclassification.
    if (!(std::abs(values[line]) < margins.near_px)) {
      return values[line] > 0 ? kSlotOne : kSlotZero;
    }
    for (int k = 0; k < px.num_lines; ++k) {
      if (pixel_lines_[px.first_line + k] == line) return static_cast<uint8_t>(k);
    }
    pixel_lines_.push_back(line);
    return static_cast<uint8_t>(px.num_lines++);
  };
  if (camera_) {
    // A line at or beyond near_px only counts by its side (the rectangles' tests and slots
    // compare the distances with +-near_px): (l . p)^2 >= near_px^2 |M^T l_xy|^2 says so
    // without the root and the division.
    constexpr double kFarPx = 1e30;  // A line's distance where only its side matters.
    const Eigen::Matrix2d mmt = at.m * at.m.transpose();
    const double near_sq = margins.near_px * margins.near_px;
    for (size_t l = 0; l < lines.raw.size(); ++l) {
      const double value = lines.raw[l].dot(at.p);
      const double norm_sq = mmt(0, 0) * lines.squares[l].x() + mmt(0, 1) * lines.squares[l].y() +
                             mmt(1, 1) * lines.squares[l].z();
      values[l] = value * value >= near_sq * norm_sq ? (value > 0 ? kFarPx : -kFarPx)
                                                     : value / std::sqrt(norm_sq);
    }
  }
  bool include = false;
  for (const Layout::Rect& rect : layout_.rects) {
    const double inside_min =
        std::min({values[rect.x0], -values[rect.x1], values[rect.y0], -values[rect.y1]});
    include |= inside_min > -margins.include_px && inside_min < margins.include_px;
    if (inside_min >= margins.near_px) {
      ++px.deep;
    } else if (inside_min > -margins.near_px && px.num_lines <= kMaxLinesPerPixel - 4) {
      pixel_rects_.push_back({slot(rect.x0), slot(rect.x1), slot(rect.y0), slot(rect.y1)});
      ++px.num_rects;
    }
  }
  if (include) {
    pixels_.push_back(px);
    if (camera_) pixel_jacobians_.push_back(at.m);
  } else {
    pixel_lines_.resize(px.first_line);
    pixel_rects_.resize(px.first_rect);
  }
}

bool TagFit::EnoughPixels(long inside, long outside, PhotometricFitResult* result) const {
  if (outside > options_.max_outside_fraction * static_cast<double>(inside + outside)) {
    result->failure = FitFailure::kImageBorder;
    result->message = "the tag's region is cut by the image border or the lens's edge (" +
                      std::to_string(outside) + " of " + std::to_string(inside + outside) +
                      " px outside)";
    return false;
  }
  if (static_cast<int>(pixels_.size()) < options_.min_pixels) {
    result->failure = FitFailure::kTooFewPixels;
    result->message = "the tag's region has " + std::to_string(pixels_.size()) +
                      " usable pixels (min_pixels " + std::to_string(options_.min_pixels) + ")";
    return false;
  }
  return true;
}

bool TagFit::Classify(const ParamVector& x, PhotometricFitResult* result) {
  left_out_pixels_ = 0;
  pixels_.clear();
  pixel_lines_.clear();
  pixel_rects_.clear();
  pixel_jacobians_.clear();
  const Eigen::Matrix3d g = HomographyOf(x);
  const double reach = EdgeProfileReachPx(x[kSigma]);
  // Margin: corners may move kReclassifyPx before the pixels are classified again. Flat pixels are
  // included up to the same margin.
  const ClassifyMargins margins{reach + kReclassifyPx, reach + kReclassifyPx};
  PatternLines lines;
  if (!LinesUnder(g, 0, &lines)) {
    result->failure = FitFailure::kDiverged;
    result->message = "degenerate homography";
    return false;
  }
  RegionBox region;
  if (!RegionInImage(g, &region, result)) return false;
  // With a camera each row is cut to the outline (OutlineRowSpan); not when a point of the
  // outline has no pixel (past the lens's valid region): the box then.
  bool outline_spans = camera_ != nullptr;
  for (const Eigen::Vector2d& p : region.outline) outline_spans &= p.allFinite();
  // Pixels within the PSF's reach of the lens's edge (the boundary of its valid region: an
  // omnidirectional lens's image circle, an equidistant lens's 90 deg) hold what the lens model
  // cannot describe: the image circle's blurred rim, or a renderer's background past the model.
  // They count as outside, like pixels past the image border. The valid region is convex in
  // pixels, so when the region box's corners, grown by that reach, have rays, every pixel has.
  const double lens_edge_reach = reach + 0.5;
  bool near_lens_edge = false;
  if (camera_) {
    for (const double u : {region.u0 - lens_edge_reach, region.u1 + lens_edge_reach}) {
      for (const double v : {region.v0 - lens_edge_reach, region.v1 + lens_edge_reach}) {
        near_lens_edge |= !HasRay(Eigen::Vector2d(u, v));
      }
    }
  }
  long inside = 0, outside = 0;
  const int i0 = static_cast<int>(std::floor(region.u0));
  const int i1 = static_cast<int>(std::ceil(region.u1));
  const int j0 = static_cast<int>(std::floor(region.v0));
  const int j1 = static_cast<int>(std::ceil(region.v1));
  std::vector<double> line_values(lines.scaled.size()), line_steps(lines.scaled.size());
  for (int j = j0; j <= j1; ++j) {
    // The row's span inside the region: each limit line is linear in i along the row.
    double lo = i0, hi = i1;
    RowSpan(j, region, outline_spans, lines, reach, &lo, &hi);
    if (!(lo <= hi)) continue;  // The region misses the row (RowSpan's empty span is +-1e300).
    lo = std::max(lo, i0 - 1.0), hi = std::min(hi, i1 + 1.0);  // In int range: the loop's bounds.
    const int row_lo = static_cast<int>(std::floor(lo)), row_hi = static_cast<int>(std::ceil(hi));
    const int first_i = std::max(i0, row_lo);
    if (!camera_) {  // Along the row each line's distance grows by a constant: l.x / S a pixel.
      for (size_t l = 0; l < lines.scaled.size(); ++l) {
        line_values[l] = lines.scaled[l].dot(
            Eigen::Vector3d((first_i - 1 - centre_.x()) / scale_, (j - centre_.y()) / scale_, 1));
        line_steps[l] = lines.scaled[l].x() / scale_;
      }
    }
    for (int i = first_i; i <= std::min(i1, row_hi); ++i) {
      if (!camera_) {
        for (size_t l = 0; l < lines.scaled.size(); ++l) line_values[l] += line_steps[l];
      }
      PixelAt at{i, j, Eigen::Vector3d((i - centre_.x()) / scale_, (j - centre_.y()) / scale_, 1),
                 Eigen::Matrix2d::Identity() / scale_};
      if (camera_) {
        Eigen::Vector2d p_hat;
        if (!ModelOf(Eigen::Vector2d(i, j), &p_hat)) continue;
        at.p = p_hat.homogeneous();
        at.m = ModelJacobian(p_hat);
      }
      // Signed distance (px) to line l: (l . p^~) / |M^T l_xy| (the model's gradient in pixels).
      auto distance = [&](size_t l) {
        return camera_ ? lines.raw[l].dot(at.p) / (at.m.transpose() * lines.raw[l].head<2>()).norm()
                       : lines.scaled[l].dot(at.p);
      };
      bool in_region = true;
      for (int k = 0; k < 4 && in_region; ++k) {
        in_region = kLimitSign[k] * distance(layout_.limits[k]) > reach;
      }
      if (!in_region) continue;
      if (i < 0 || j < 0 || i >= image_.width || j >= image_.height ||
          (near_lens_edge && !RaysAround(Eigen::Vector2d(i, j), lens_edge_reach))) {
        ++outside;
        continue;
      }
      ++inside;
      const size_t kept = pixels_.size(), kept_lines = pixel_lines_.size(),
                   kept_rects = pixel_rects_.size();
      AddPixel(at, lines, margins, &line_values);
      // A pixel the robust pass left out is classified like the others, counted, and dropped.
      if (pixels_.size() > kept && !left_out_.empty() &&
          std::binary_search(left_out_.begin(), left_out_.end(), pixels_.back().key)) {
        pixels_.pop_back();
        if (camera_) pixel_jacobians_.pop_back();
        pixel_lines_.resize(kept_lines);
        pixel_rects_.resize(kept_rects);
        ++left_out_pixels_;
      }
    }
  }
  if (!EnoughPixels(inside, outside, result)) return false;
  CornersOf(g, &classified_corners_);
  classified_sigma_ = x[kSigma];
  return true;
}

namespace {

// The quadrature rules per rho, built once per vertex: without a lens every pixel of a vertex has
// the same rho (its two lines' normals), so a few entries serve the whole tag.
class QuadrantRules {
 public:
  const QuadrantRule& For(double rho) {
    for (int i = 0; i < num_; ++i) {
      if (rules_[i].rho == rho) return rules_[i];
    }
    const int slot = next_;
    next_ = (next_ + 1) % static_cast<int>(rules_.size());
    num_ = std::max(num_, slot + 1);
    rules_[slot] = QuadrantRuleFor(rho);
    return rules_[slot];
  }

 private:
  std::array<QuadrantRule, 16> rules_;
  int num_ = 0, next_ = 0;
};

// The model's normalised brightness b at a pixel (0 white, 1 black) and d b / d sigma: its deep
// rectangles, plus per near rectangle [P(f_x0) - P(f_x1)] [P(f_y0) - P(f_y1)] and the quadrant
// corrections at its vertices (tag_model.h). Adds d b / d f to lines->weight per slot.
struct Brightness {
  double b, db_dsigma;
};
// The PSF's sigma (px) and its total variance with the pixel box, s2 = sigma^2 + 1/12.
struct Psf {
  double sigma, s2, inv_s;
  explicit Psf(double sigma_px)
      : sigma(sigma_px), s2(sigma_px * sigma_px + 1.0 / 12), inv_s(1 / std::sqrt(s2)) {}
};
Brightness PixelBrightness(const FitPixel& px, const RectSlots* rects, const Psf& psf,
                           PixelLines* lines, QuadrantRules* rules) {
  const double sigma = psf.sigma, s2 = psf.s2, inv_s = psf.inv_s;
  const auto& profile = lines->profile;
  auto& weight = lines->weight;
  double b = px.deep, db_dsigma = 0;
  for (int k = 0; k < px.num_rects; ++k) {
    const RectSlots& r = rects[k];
    const EdgeProfileValue &a0 = profile[r[0]], &a1 = profile[r[1]];
    const EdgeProfileValue &c0 = profile[r[2]], &c1 = profile[r[3]];
    const double fx = a0.p - a1.p, fy = c0.p - c1.p;
    b += fx * fy;
    db_dsigma += (a0.dp_dsigma - a1.dp_dsigma) * fy + (c0.dp_dsigma - c1.dp_dsigma) * fx;
    weight[r[0]] += a0.dp_dd * fy;
    weight[r[1]] -= a1.dp_dd * fy;
    weight[r[2]] += c0.dp_dd * fx;
    weight[r[3]] -= c1.dp_dd * fx;
    // The vertices whose two edges are within reach and not orthogonal in the image: the
    // quadrant {x > x_i, y > y_j} enters the rectangle with the sign (-1)^(i + j).
    for (int i = 0; i < 2; ++i) {
      for (int j = 2; j < 4; ++j) {
        const int sx = r[i], sy = r[j];
        if (sx >= kMaxLinesPerPixel || sy >= kMaxLinesPerPixel) continue;
        const double rho = lines->normal[sx].dot(lines->normal[sy]);
        const double qa = lines->distance[sx] * inv_s, qb = lines->distance[sy] * inv_s;
        if (std::abs(rho) < 1e-4 || std::abs(qa) > kQuadrantCorrectionReach ||
            std::abs(qb) > kQuadrantCorrectionReach) {
          continue;
        }
        const QuadrantCorrection c = QuadrantCorrectionAt(qa, qb, rules->For(rho));
        const double sign = (i + j) % 2 == 0 ? 1.0 : -1.0;
        b += sign * c.c;
        weight[sx] += sign * c.dc_da * inv_s;
        weight[sy] += sign * c.dc_db * inv_s;
        // a = d / s, ds/dsigma = sigma / s: da/dsigma = -a sigma / s^2.
        db_dsigma -= sign * (qa * c.dc_da + qb * c.dc_db) * sigma / s2;
      }
    }
  }
  return {b, db_dsigma};
}

// Adds the pixel's row jac to the upper triangle of J^T J (column-major) and jac r to J^T r,
// from parameter `first` on (the others are zero).
void AccumulateNormalEquations(const ParamVector& jac, double r, int first, ParamMatrix* jtj,
                               ParamVector* jtr) {
  double* h = jtj->data();
  for (int col = first; col < kNumParams; ++col) {
    const double jc = jac[col];
    for (int row = first; row <= col; ++row) h[col * kNumParams + row] += jac[row] * jc;
  }
  for (int i = first; i < kNumParams; ++i) (*jtr)[i] += jac[i] * r;
}

}  // namespace

void TagFit::ProfileLines(size_t index, const Eigen::Vector3d& p, const PatternLines& lines,
                          const std::array<EdgeProfileTable, 2>& tables, PixelLines* out) const {
  const FitPixel& px = pixels_[index];
  const int* lines_of_pixel = pixel_lines_.data() + px.first_line;
  for (int k = 0; k < px.num_lines; ++k) {
    const int line = lines_of_pixel[k];
    double f;
    if (camera_) {
      const Eigen::Matrix2d& m = pixel_jacobians_[index];
      const Eigen::Vector2d mt_l = m.transpose() * lines.raw[line].head<2>();
      out->lens_inv_n[k] = 1 / mt_l.norm();
      out->lens_r[k] = m * mt_l * out->lens_inv_n[k];
      const double first_order = lines.raw[line].dot(p) * out->lens_inv_n[k];
      f = first_order * (1 + 0.5 * lines.spread[line] * first_order) - lines.bend_shift[line];
      out->normal[k] = mt_l * out->lens_inv_n[k];
    } else {
      f = scale_ * lines.unit[line].dot(p);
      out->normal[k] = lines.unit[line].head<2>();
    }
    out->distance[k] = f;
    out->profile[k] = layout_.lines[line].vertical ? tables[0](f) : tables[1](f);
    if (camera_) out->profile[k].dp_dsigma -= lines.bend_shift_dsigma[line] * out->profile[k].dp_dd;
  }
}

Eigen::Matrix3d TagFit::HomographyGradient(size_t index, const Eigen::Vector3d& p,
                                           const PatternLines& lines, const PixelLines& pl) const {
  const FitPixel& px = pixels_[index];
  const int* lines_of_pixel = pixel_lines_.data() + px.first_line;
  Eigen::Matrix3d dg = Eigen::Matrix3d::Zero();
  for (int k = 0; k < px.num_lines; ++k) {
    const int line = lines_of_pixel[k];
    Eigen::Vector3d df;  // weight * d f / d l.
    if (camera_) {
      // d = f + spread f^2 / 2 (PatternLines::spread): d d / d f = 1 + spread f.
      const double f = lines.raw[line].dot(p) * pl.lens_inv_n[k];
      const double w = pl.lens_inv_n[k] * pl.weight[k] * (1 + lines.spread[line] * f);
      df = Eigen::Vector3d(w * (p.x() - f * pl.lens_r[k].x()), w * (p.y() - f * pl.lens_r[k].y()),
                           w);
    } else {
      const Eigen::Vector3d& u = lines.unit[line];
      const double w = scale_ * lines.inv_norm[line] * pl.weight[k], f = u.dot(p);
      df = Eigen::Vector3d(w * (p.x() - f * u.x()), w * (p.y() - f * u.y()), w);
    }
    const TagLine& tag_line = layout_.lines[line];
    dg.row(tag_line.vertical ? 0 : 1) += df;
    dg.row(2) += tag_line.m.z() * df;
  }
  return dg;
}

bool TagFit::Evaluate(const ParamVector& x, double* cost, ParamMatrix* jtj, ParamVector* jtr,
                      PixelResiduals* residuals) const {
  residuals->residual.assign(pixels_.size(), 0.0);
  residuals->flat.assign(pixels_.size(), false);
  const Eigen::Matrix3d g = HomographyOf(x);
  const double sigma = std::max(x[kSigma], kMinSigmaPx);
  const double black = x[kBlack], white = x[kWhite], contrast = black - white;
  const Eigen::Vector2d shading(x[kShadeX], x[kShadeY]);
  PatternLines lines;
  if (!LinesUnder(g, 1e-12, &lines)) return false;
  BendLines(sigma, &lines);
  // The edges' normals in the image (with a camera: at the tag's centre) for the pixel box.
  auto image_normal = [&](int line) -> Eigen::Vector2d {
    return (centre_jacobian_.transpose() * lines.raw[line].head<2>()).normalized();
  };
  std::array<EdgeProfileTable, 2> tables;  // Vertical, horizontal lines.
  tables[0].Build(sigma, image_normal(layout_.middle_vertical));
  tables[1].Build(sigma, image_normal(layout_.middle_horizontal));

  jtj->setZero();
  jtr->setZero();
  *cost = 0;
  PixelLines pl;
  pl.profile[kSlotZero] = {0, 0, 0};
  pl.profile[kSlotOne] = {1, 0, 0};
  QuadrantRules rules;
  const Psf psf(sigma);
  ParamVector jac;
  for (size_t index = 0; index < pixels_.size(); ++index) {
    const FitPixel& px = pixels_[index];
    const Eigen::Vector3d p(px.p.x(), px.p.y(), 1);
    if (!((g.row(2) * p)(0) > 0)) return false;  // Behind the homography's horizon.
    std::fill(pl.weight.begin(), pl.weight.begin() + px.num_lines, 0.0);
    ProfileLines(index, p, lines, tables, &pl);
    const Brightness br =
        PixelBrightness(px, pixel_rects_.data() + px.first_rect, psf, &pl, &rules);
    const double base = white + contrast * br.b;
    const double shade = 1 + shading.dot(px.p);
    double model = shade * base;
    jac.setZero();
    bool censored = false;
    if (model >= 255 || model <= 0) {
      // Saturated: the sensor clips; an equally clipped pixel carries no information.
      censored = (model >= 255 && px.gray >= 255) || (model <= 0 && px.gray <= 0);
      model = std::clamp(model, 0.0, 255.0);
    } else {
      const Eigen::Matrix3d dg = HomographyGradient(index, p, lines, pl) * (shade * contrast);
      jac << dg(0, 0), dg(0, 1), dg(0, 2), dg(1, 0), dg(1, 1), dg(1, 2), dg(2, 0), dg(2, 1),
          shade * contrast * br.db_dsigma, shade * br.b, shade * (1 - br.b), base * px.p.x(),
          base * px.p.y();
      if (!options_.fit_shading) jac[kShadeX] = jac[kShadeY] = 0;
    }
    if (censored) continue;
    const double r = px.gray - model;
    residuals->residual[index] = r;
    double slope = 0;
    for (int k = 0; k < px.num_lines; ++k) slope += std::abs(pl.weight[k]);
    residuals->flat[index] = slope < kFlatSlopePerPx;
    *cost += r * r;
    // A pixel beyond every edge's reach depends only on the levels and the shading.
    AccumulateNormalEquations(jac, r, px.num_rects == 0 ? kBlack : 0, jtj, jtr);
  }
  *jtj = jtj->selfadjointView<Eigen::Upper>();
  return true;
}

}  // namespace photometric_internal
}  // namespace calibench
