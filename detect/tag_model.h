// The model of a decoded AprilTag that the photometric fit (photometric_fit.h) draws: its black
// pattern in tag coordinates, and the profile of one of its edges blurred by a Gaussian PSF and
// integrated over the pixel box.
//
// Tag coordinates (cells): x to the right along the bitmap's columns, y up (board y, the bitmap's
// row 0 is the top); the black reference square spans [0, W]^2 (W = width_at_border), so the
// detector's corners 0..3 (bottom-left, bottom-right, top-right, top-left) are (0, 0), (W, 0),
// (W, W), (0, W). Pixels follow calibench's convention (pixel (i, j) centred at (i, j)).
//
// b(p), the blurred, pixel-integrated black fraction of pixel p. The pattern's black is a union of
// axis-aligned rectangles R (maximal runs of the decoded bitmap's black cells, and Kalibr's corner
// squares); each maps to a quadrilateral in the image whose edge
// lines e have signed distances d_e(p) (px, > 0 inside). Then
//   b(p) = sum_R  [P(d_x0) + P(d_x1) - 1] [P(d_y0) + P(d_y1) - 1]
// where P(d) is the 1D profile of a straight edge: the fraction of a pixel at distance d inside
// the black covered after the PSF, i.e. the CDF at d of  U(|n_x|) + U(|n_y|) + N(0, sigma^2)
// (the pixel box projected on the edge normal n is the sum of two uniforms of widths |n_x|, |n_y|):
//   P(d) = [Q(d+a+b') - Q(d+a-b') - Q(d-a+b') + Q(d-a-b')] / (|n_x| |n_y|),
//   a = |n_x| / 2, b' = |n_y| / 2,
//   Q(x) = (x^2 + sigma^2)/2 Phi(x/sigma) + x sigma/2 phi(x/sigma)   (Q'' = Phi(x / sigma)),
//   dQ/dsigma = sigma Phi(x/sigma).
// The product form is exact for a rectangle that maps to a rectangle (orthogonal edges) and for
// every straight edge and parallel strip; at a vertex whose edges are not orthogonal in the image
// it is completed by the quadrant correction below. Collinear edges of adjacent rectangles are one
// image line, so the sum has no seams.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "sim/tag_family.h"

namespace calibench {

// The tag's black pattern in tag coordinates (see above).
struct TagPattern {
  struct Rect {
    double x0, y0, x1, y1;  // Cells, x0 < x1, y0 < y1.
  };
  int width_cells = 8;              // W.
  double white_margin_cells = 1.0;  // Known white (or corner squares) around the black square.
  std::vector<Rect> black;
  // Tag `id` of `family` (its bitmap's black cells inside the reference square, as maximal
  // rectangles), with a white margin of `white_margin_cells` and, when corner_square_cells > 0,
  // Kalibr's black squares of that side at the four corners. False (and *why) for a bad id.
  static bool FromFamily(const TagFamily& family, int id, double white_margin_cells,
                         double corner_square_cells, TagPattern* pattern, std::string* why);
  // Tag `id` as an AprilGrid prints it (the pattern FrameDetector fits): the white between tags,
  // tag_spacing of the black square's side, at least the family's own white ring; with
  // corner_squares, Kalibr's squares of that gap's side at its corners. False as FromFamily.
  static bool OnGrid(const TagFamily& family, int id, double tag_spacing, bool corner_squares,
                     TagPattern* pattern, std::string* why);
};

// The edge profile P(d) above and its derivatives dP/dd, dP/dsigma, for an edge whose image
// normal is (nx, ny) (unit).
struct EdgeProfileValue {
  double p, dp_dd, dp_dsigma;
};
EdgeProfileValue EdgeProfile(double d, double sigma, double nx, double ny);

// Two edges that cross at angle other than 90 deg (a sheared rectangle's vertex: perspective, or a
// lens's anisotropic scale). The blurred quadrant on the positive side of both, with normals n1, n2
// (unit, towards the quadrant) and signed distances d1, d2, is the bivariate normal CDF
// Phi2(d1 / s, d2 / s; rho), rho = n1 . n2, s = sqrt(sigma^2 + 1/12) (the pixel box taken as a
// Gaussian of its variance). The product of the two edges' profiles is its rho = 0 value; the
// correction C = Phi2(a, b; rho) - Phi(a) Phi(b) = (1 / 2 pi) int_0^asin(rho) exp(-(a^2 + b^2 -
// 2 a b sin t) / (2 cos^2 t)) dt (Plackett's identity) completes it. Its derivatives are those of
// the quadrature below (the integrand's a-derivative, -(a - b sin t) / cos^2 t times it, at the
// same nodes): the exact gradient of the C that the fit evaluates, equal to the closed form
//   dC/da = phi(a) [Phi((b - rho a) / sqrt(1 - rho^2)) - Phi(b)]   (and symmetrically in b)
// to 1e-7 (the value's own error is 5e-8), at the cost of no erfc and no exponential beyond the
// nodes'.
// A rectangle is then the signed sum of the quadrants at its four vertices.
struct QuadrantCorrection {
  double c, dc_da, dc_db;
};
// The quadrature for one rho: Gauss-Legendre nodes on [0, asin(rho)], as few as keep the error
// below 5e-8 for |a|, |b| <= 5 (2 nodes to |rho| 0.2, 4 to 0.5, 6 to 0.7, 8 to 0.9, 16 beyond, to
// the clamp at 0.99). It depends on rho alone, so a fit builds it once per vertex and
// evaluates every pixel with exponentials only.
struct QuadrantRule {
  double rho = 0;  // As given; the quadrature uses it clamped to [-0.99, 0.99].
  int num_nodes = 0;
  double half = 0;  // asin(rho) / 2.
  std::array<double, 16> weight{}, sin_t{}, inv_2cos2{};
  double clamped = 0;  // rho clamped.
};
QuadrantRule QuadrantRuleFor(double rho);
QuadrantCorrection QuadrantCorrectionAt(double a, double b, const QuadrantRule& rule);
inline QuadrantCorrection QuadrantCorrectionAt(double a, double b, double rho) {
  return QuadrantCorrectionAt(a, b, QuadrantRuleFor(rho));
}
// Beyond this |a| or |b| the correction is below 2e-7: it is not computed.
constexpr double kQuadrantCorrectionReach = 5.0;

// Reach of the profile: beyond it, P is 0 or 1 to < 3e-4 of the contrast (3.5 sigma of the PSF plus
// the pixel box's half diagonal).
inline double EdgeProfileReachPx(double sigma) { return 3.5 * sigma + 0.75; }

// P, dP/dd and dP/dsigma tabulated on a fine grid for one sigma and one edge direction (the lines
// of one family of a tag are nearly parallel in the image: one table per family).
class EdgeProfileTable {
 public:
  void Build(double sigma, const Eigen::Vector2d& normal);
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

}  // namespace calibench
