#include "detect/tag_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace calibench {
namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;
constexpr double kInvSqrt2Pi = 0.39894228040143267794;

double Phi(double u) { return 0.5 * std::erfc(-u * kInvSqrt2); }
double PhiDensity(double u) { return kInvSqrt2Pi * std::exp(-0.5 * u * u); }

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

QuadrantRule QuadrantRuleFor(double rho) {
  // Gauss-Legendre nodes and weights on [-1, 1], positive half (the rule is symmetric).
  static constexpr double kNodes2[1] = {0.5773502691896258};
  static constexpr double kWeights2[1] = {1.0};
  static constexpr double kNodes4[2] = {0.3399810435848563, 0.8611363115940526};
  static constexpr double kWeights4[2] = {0.6521451548625461, 0.3478548451374538};
  static constexpr double kNodes6[3] = {0.2386191860831969, 0.6612093864662645, 0.9324695142031521};
  static constexpr double kWeights6[3] = {0.4679139345726910, 0.3607615730481386,
                                          0.1713244923791704};
  static constexpr double kNodes8[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                        0.9602898564975363};
  static constexpr double kWeights8[4] = {0.3626837833783620, 0.3137066458778873,
                                          0.2223810344533745, 0.1012285362903763};
  static constexpr double kNodes16[8] = {0.0950125098376375, 0.2816035507792589, 0.4580167776572274,
                                         0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                                         0.9445750230732326, 0.9894009349916499};
  static constexpr double kWeights16[8] = {
      0.1894506104550686, 0.1826034150449236, 0.1691565193950026, 0.1495959888165768,
      0.1246289712555340, 0.0951585116824926, 0.0622535239386477, 0.0271524594117540};
  QuadrantRule rule;
  rule.rho = rho;
  rule.clamped = std::clamp(rho, -0.99, 0.99);
  rule.half = 0.5 * std::asin(rule.clamped);
  const double abs_rho = std::abs(rule.clamped);
  const double *nodes = kNodes8, *weights = kWeights8;
  int pairs = 4;
  if (abs_rho <= 0.2) {
    nodes = kNodes2, weights = kWeights2, pairs = 1;
  } else if (abs_rho <= 0.5) {
    nodes = kNodes4, weights = kWeights4, pairs = 2;
  } else if (abs_rho <= 0.7) {
    nodes = kNodes6, weights = kWeights6, pairs = 3;
  } else if (abs_rho > 0.9) {
    nodes = kNodes16, weights = kWeights16, pairs = 8;
  }
  for (int i = 0; i < pairs; ++i) {
    for (const double t : {rule.half * (1 - nodes[i]), rule.half * (1 + nodes[i])}) {
      const double c = std::cos(t);
      rule.weight[rule.num_nodes] = weights[i];
      rule.sin_t[rule.num_nodes] = std::sin(t);
      rule.inv_2cos2[rule.num_nodes] = 1 / (2 * c * c);
      ++rule.num_nodes;
    }
  }
  return rule;
}

QuadrantCorrection QuadrantCorrectionAt(double a, double b, const QuadrantRule& rule) {
  // C = (half / 2 pi) sum_k w_k e_k, e_k = exp(-(a^2 + b^2 - 2 a b s_k) c_k), and the
  // quadrature's own gradient dC/da = (half / 2 pi) sum_k w_k e_k (-2 c_k) (a - b s_k) (and
  // symmetrically in b): exponentials only.
  const double q = a * a + b * b, ab2 = 2 * a * b;
  double sum = 0, sum_da = 0, sum_db = 0;
  for (int k = 0; k < rule.num_nodes; ++k) {
    const double s = rule.sin_t[k], c = rule.inv_2cos2[k];
    const double we = rule.weight[k] * std::exp(-(q - ab2 * s) * c);
    sum += we;
    sum_da -= we * c * (a - b * s);
    sum_db -= we * c * (b - a * s);
  }
  const double scale = rule.half / (2 * M_PI);
  return {sum * scale, 2 * sum_da * scale, 2 * sum_db * scale};
}

bool TagPattern::OnGrid(const TagFamily& family, int id, double tag_spacing, bool corner_squares,
                        TagPattern* pattern, std::string* why) {
  const double gap_cells = tag_spacing * family.width_at_border();
  return FromFamily(family, id, std::max(gap_cells, static_cast<double>(family.border_start())),
                    corner_squares ? gap_cells : 0.0, pattern, why);
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

void EdgeProfileTable::Build(double sigma, const Eigen::Vector2d& normal) {
  reach_ = EdgeProfileReachPx(sigma);
  const int n = static_cast<int>(std::ceil(2 * reach_ * kPerPx)) + 1;
  values_.resize(n);
  for (int i = 0; i < n; ++i) {
    values_[i] = EdgeProfile(-reach_ + i / kPerPx, sigma, normal.x(), normal.y());
  }
}

}  // namespace calibench
