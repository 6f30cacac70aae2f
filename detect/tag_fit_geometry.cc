// The photometric fit's geometry (tag_fit.h): the pattern's lines in tag coordinates (its layout),
// the model plane a pixel maps to (the pixels themselves, or with a camera the tangent plane about
// the tag's centre ray) and back, the homography that starts the fit, and the pattern's lines
// under a homography, with their bend through the camera.
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "detect/tag_fit.h"

namespace calibench {
namespace photometric_internal {

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

bool TagFit::ModelOf(const Eigen::Vector2d& pixel, Eigen::Vector2d* p_hat) const {
  if (!camera_) {
    *p_hat = (pixel - centre_) / scale_;
    return true;
  }
  Eigen::Vector3d ray;
  Eigen::Vector2d q;
  if (!HasRay(pixel, &ray) || !plane_.FromRay(ray, &q)) return false;
  *p_hat = (q - centre_) / scale_;
  return true;
}

Eigen::Vector2d TagFit::ToPixel(const Eigen::Vector2d& p_hat) const {
  if (!camera_) return centre_ + scale_ * p_hat;
  Eigen::Vector2d pixel(std::numeric_limits<double>::quiet_NaN(), 0);
  plane_.ToPixel(*camera_, centre_ + scale_ * p_hat, &pixel);
  return pixel;
}

bool TagFit::HasRay(const Eigen::Vector2d& pixel, Eigen::Vector3d* ray) const {
  // UnprojectToRay, with A^-1 computed once.
  Eigen::Vector3d unused;
  return RayOfDistorted(*camera_, (a_inv_ * pixel.homogeneous()).hnormalized(),
                        ray ? ray : &unused);
}

bool TagFit::RaysAround(const Eigen::Vector2d& pixel, double radius) const {
  const double diagonal = radius * M_SQRT1_2;
  for (const Eigen::Vector2d& step :
       {Eigen::Vector2d(radius, 0), Eigen::Vector2d(-radius, 0), Eigen::Vector2d(0, radius),
        Eigen::Vector2d(0, -radius), Eigen::Vector2d(diagonal, diagonal),
        Eigen::Vector2d(diagonal, -diagonal), Eigen::Vector2d(-diagonal, diagonal),
        Eigen::Vector2d(-diagonal, -diagonal)}) {
    if (!HasRay(pixel + step)) return false;
  }
  return true;
}

Eigen::Matrix2d TagFit::PixelJacobian(const Eigen::Vector2d& p_hat) const {
  if (!camera_) return scale_ * Eigen::Matrix2d::Identity();
  // Central differences of the projection (smooth, no iteration).
  constexpr double h = 1e-6;
  Eigen::Matrix2d forward;
  for (int a = 0; a < 2; ++a) {
    const Eigen::Vector2d e = Eigen::Vector2d::Unit(a) * h;
    forward.col(a) = (ToPixel(p_hat + e) - ToPixel(p_hat - e)) / (2 * h);
  }
  return forward;
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

bool TagFit::LinesUnder(const Eigen::Matrix3d& g, double min_norm, PatternLines* lines) const {
  const size_t n_lines = layout_.lines.size();
  lines->raw.resize(n_lines), lines->unit.resize(n_lines), lines->scaled.resize(n_lines);
  lines->inv_norm.resize(n_lines), lines->squares.resize(n_lines);
  for (size_t i = 0; i < n_lines; ++i) {
    const Eigen::Vector3d l = g.transpose() * layout_.lines[i].m;
    const double n = l.head<2>().norm();
    if (!(n > min_norm)) return false;
    lines->raw[i] = l;
    lines->unit[i] = l / n;
    lines->scaled[i] = scale_ * l / n;
    lines->inv_norm[i] = 1 / n;
    lines->squares[i] = Eigen::Vector3d(l.x() * l.x(), 2 * l.x() * l.y(), l.y() * l.y());
  }
  return true;
}

void TagFit::BendLines(double sigma, PatternLines* lines) const {
  const size_t n_lines = lines->raw.size();
  lines->bend_shift.assign(n_lines, 0.0);
  lines->bend_shift_dsigma.assign(n_lines, 0.0);
  lines->spread.assign(n_lines, 0.0);
  if (!camera_) return;
  constexpr double kStep = 0.25;  // Along the line, in p^ (the tag spans about [-1, 1]).
  const double half_var = 0.5 * (sigma * sigma + 1.0 / 12);
  for (size_t i = 0; i < n_lines; ++i) {
    const Eigen::Vector3d& l = lines->raw[i];
    const double n2 = l.head<2>().squaredNorm();
    if (!(n2 > 0)) continue;
    const Eigen::Vector2d foot = -l.z() / n2 * l.head<2>();  // Nearest the centre p^ = 0.
    const Eigen::Vector2d along = Eigen::Vector2d(-l.y(), l.x()) / std::sqrt(n2);
    const Eigen::Vector2d before = ToPixel(foot - kStep * along), at = ToPixel(foot),
                          after = ToPixel(foot + kStep * along);
    const Eigen::Vector2d velocity = (after - before) / (2 * kStep);
    const Eigen::Vector2d acceleration = (after - 2 * at + before) / (kStep * kStep);
    const double speed2 = velocity.squaredNorm();
    // The + side's image normal: perpendicular to the curve, towards where l . p grows.
    const Eigen::Vector2d towards_plus = PixelJacobian(foot) * l.head<2>();
    Eigen::Vector2d normal(-velocity.y(), velocity.x());
    if (normal.dot(towards_plus) < 0) normal = -normal;
    const double kappa = acceleration.dot(normal) / (std::sqrt(speed2) * speed2);
    if (!std::isfinite(kappa)) continue;
    lines->bend_shift[i] = kappa * half_var;
    lines->bend_shift_dsigma[i] = kappa * sigma;
    // N = |M^T l_xy| one pixel either side of the curve, along its image normal.
    constexpr double kAcrossPx = 1.0;
    const Eigen::Vector2d unit_normal = normal.normalized();
    double log_n[2];
    bool across = true;
    for (int side = 0; side < 2 && across; ++side) {
      Eigen::Vector2d p_hat;
      across = ModelOf(at + (side == 0 ? -kAcrossPx : kAcrossPx) * unit_normal, &p_hat);
      if (across) log_n[side] = std::log((ModelJacobian(p_hat).transpose() * l.head<2>()).norm());
    }
    const double spread = across ? (log_n[1] - log_n[0]) / (2 * kAcrossPx) : 0.0;
    if (std::isfinite(spread)) lines->spread[i] = spread;
  }
}

}  // namespace photometric_internal
}  // namespace calibench
