#include "detect/corner_refinement.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <optional>
#include <vector>

namespace calibench {
namespace {

// Bilinear interpolation at (u, v) in calibench's pixel convention (pixel (i, j) centred at (i,
// j)).
std::optional<double> Sample(const GrayImageView& image, double u, double v) {
  const int i = static_cast<int>(std::floor(u)), j = static_cast<int>(std::floor(v));
  if (i < 0 || j < 0 || i + 1 >= image.width || j + 1 >= image.height) return std::nullopt;
  const double a = u - i, b = v - j;
  return (1 - a) * (1 - b) * image.at(i, j) + a * (1 - b) * image.at(i + 1, j) +
         (1 - a) * b * image.at(i, j + 1) + a * b * image.at(i + 1, j + 1);
}

// Line n . x = c fitted by total least squares; nullopt with fewer than 4 points.
// With curved_edges, the parabola s(t) = a + b t + c2 t^2 about `origin` along `along`, s measured
// along `normal` (a = b = c2 = 0: the line itself).
struct Line {
  Eigen::Vector2d normal;
  double c;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero(), along = Eigen::Vector2d::Zero();
  double a = 0, b = 0, c2 = 0;
  // g(x) = 0 on the curve, and its gradient.
  double Residual(const Eigen::Vector2d& x) const {
    const double t = (x - origin).dot(along);
    return (x - origin).dot(normal) - (a + t * (b + t * c2));
  }
  Eigen::Vector2d Gradient(const Eigen::Vector2d& x) const {
    const double t = (x - origin).dot(along);
    return normal - (b + 2 * c2 * t) * along;
  }
};

// The parabola through `points` in the frame of their TLS line `line`.
std::optional<Line> FitParabola(const std::vector<Eigen::Vector2d>& points, Line line) {
  if (points.size() < 6) return std::nullopt;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  line.origin = mean;
  line.along = Eigen::Vector2d(-line.normal.y(), line.normal.x());
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const Eigen::Vector2d& p : points) {
    const double t = (p - mean).dot(line.along), s = (p - mean).dot(line.normal);
    const Eigen::Vector3d row(1, t, t * t);
    ata += row * row.transpose();
    atb += row * s;
  }
  const Eigen::Vector3d coeffs = ata.ldlt().solve(atb);
  if (!coeffs.allFinite()) return std::nullopt;
  line.a = coeffs[0], line.b = coeffs[1], line.c2 = coeffs[2];
  return line;
}
std::optional<Line> FitLine(const std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 4) return std::nullopt;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  const Eigen::Vector2d normal = eig.eigenvectors().col(0);
  return Line{normal, normal.dot(mean)};
}

}  // namespace

bool CornerRefineOptions::Check(std::string* why) const {
  std::string msg;
  if (samples_per_edge < 4) msg = "samples_per_edge must be >= 4";
  if (!(corner_margin >= 0 && corner_margin < 0.5)) msg = "corner_margin must lie in [0, 0.5)";
  if (!(max_search_px > 0)) msg = "max_search_px must be > 0";
  if (!(max_correction_px > 0)) msg = "max_correction_px must be > 0";
  if (width_at_border < 3) msg = "width_at_border must be >= 3";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

namespace {

// One pass: the four edge lines measured around the quadrilateral `p`, and their intersections.
// The edge's position along `normal` (dark inside to bright outside) across the window
// [-h, h] about `base`, from the area under the normalised profile (sampled every 0.05 px). None
// when the window leaves the image, has no contrast, or the edge is not inside it.
std::optional<Eigen::Vector2d> EdgePointAcross(const GrayImageView& image,
                                               const Eigen::Vector2d& base,
                                               const Eigen::Vector2d& normal, double h) {
  constexpr double kStep = 0.05;
  const int n = static_cast<int>(std::round(2 * h / kStep)) + 1;
  std::vector<double> profile(n);
  for (int s = 0; s < n; ++s) {
    const std::optional<double> v = Sample(image, base.x() + (-h + s * kStep) * normal.x(),
                                           base.y() + (-h + s * kStep) * normal.y());
    if (!v) return std::nullopt;
    profile[s] = *v;
  }
  // Plateau levels: the mean of the profile's first and last kPlateau samples.
  constexpr int kPlateau = 5;
  double dark = 0, bright = 0;
  for (int s = 0; s < kPlateau; ++s) {
    dark += profile[s] / kPlateau;
    bright += profile[n - 1 - s] / kPlateau;
  }
  if (bright - dark < 10.0) return std::nullopt;  // No contrast: not an edge here.
  // Area estimate: for a step from dark to bright at offset e in [-h, h], the normalised
  // profile q = (v - dark) / (bright - dark) integrates to h - e. Unlike a mid-level crossing
  // of the interpolated profile (biased by up to 0.09 px depending on the edge's sub-pixel
  // phase), the area is exact for area-sampled pixels and any symmetric blur.
  double area = 0;
  for (int s = 1; s < n; ++s) {
    area += 0.5 * kStep * (profile[s - 1] + profile[s] - 2 * dark) / (bright - dark);
  }
  const double offset = (n - 1) * kStep / 2 - area;  // e, with the window's centre at 0.
  if (std::abs(offset) >= h) return std::nullopt;
  return base + offset * normal;
}

// Corner k joins edge (k-1 -> k) and edge (k -> k+1): the lines' intersection, then with curved
// edges Newton on (g1, g2) = 0 from it. False for parallel edges or curves that do not meet
// near the lines' corner.
bool IntersectEdges(const std::array<Line, 4>& lines, bool curved_edges,
                    std::array<Eigen::Vector2d, 4>* out) {
  for (int k = 0; k < 4; ++k) {
    const Line& l1 = lines[(k + 3) % 4];
    const Line& l2 = lines[k];
    Eigen::Matrix2d m;
    m << l1.normal.transpose(), l2.normal.transpose();
    if (std::abs(m.determinant()) < 1e-6) return false;
    Eigen::Vector2d x = m.inverse() * Eigen::Vector2d(l1.c, l2.c);
    // Curves: the lines' intersection is a few hundredths of a pixel away; 2-3 steps.
    bool converged = !curved_edges;
    for (int it = 0; curved_edges && it < 10 && !converged; ++it) {
      Eigen::Matrix2d j;
      j << l1.Gradient(x).transpose(), l2.Gradient(x).transpose();
      if (std::abs(j.determinant()) < 1e-6) return false;
      const Eigen::Vector2d step = j.inverse() * Eigen::Vector2d(l1.Residual(x), l2.Residual(x));
      x -= step;
      converged = step.norm() < 1e-9;
    }
    if (!converged) return false;
    (*out)[k] = x;
  }
  return true;
}

bool RefinePass(const GrayImageView& image, const CornerRefineOptions& o,
                const std::array<Eigen::Vector2d, 4>& p, std::array<Eigen::Vector2d, 4>* out) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& c : p) centre += c / 4.0;
  std::array<Line, 4> lines;
  for (int e = 0; e < 4; ++e) {
    const Eigen::Vector2d& a = p[e];
    const Eigen::Vector2d& b = p[(e + 1) % 4];
    const Eigen::Vector2d along = (b - a).normalized();
    Eigen::Vector2d normal(-along.y(), along.x());
    if (normal.dot((a + b) / 2 - centre) < 0) normal = -normal;  // Outward.
    // The window must stay inside the black ring and the white frame, one cell each across the
    // edge: the cell size across is that of the two adjacent edges (they differ under
    // perspective from this edge's own).
    const double across_px =
        0.5 * ((p[(e + 3) % 4] - a).norm() + (p[(e + 2) % 4] - b).norm()) / o.width_at_border;
    const double h = std::min(o.max_search_px, 0.45 * across_px);
    if (h < 0.75) return false;  // Tag too small to read its edges.
    std::vector<Eigen::Vector2d> edge_points;
    for (int k = 0; k < o.samples_per_edge; ++k) {
      const double t = o.corner_margin + (1 - 2 * o.corner_margin) * (k + 0.5) / o.samples_per_edge;
      const std::optional<Eigen::Vector2d> point =
          EdgePointAcross(image, a + t * (b - a), normal, h);
      if (point) edge_points.push_back(*point);
    }
    if (static_cast<int>(edge_points.size()) < o.samples_per_edge / 2) return false;
    std::optional<Line> line = FitLine(edge_points);
    if (line && o.curved_edges) line = FitParabola(edge_points, *line);
    if (!line) return false;
    lines[e] = *line;
  }
  return IntersectEdges(lines, o.curved_edges, out);
}

}  // namespace

bool RefineTagCorners(const GrayImageView& image, const CornerRefineOptions& o,
                      TagDetection* detection) {
  if (!o.Check(nullptr)) return false;
  // Pass 1 centres the profiles on the detector's corners; pass 2 re-centres them on pass 1's
  // lines, so that the window's truncation of the edge transition is symmetric.
  constexpr int kPasses = 2;
  std::array<Eigen::Vector2d, 4> corners = detection->corners;
  for (int pass = 0; pass < kPasses; ++pass) {
    std::array<Eigen::Vector2d, 4> refined;
    if (!RefinePass(image, o, corners, &refined)) return false;
    corners = refined;
  }
  for (int k = 0; k < 4; ++k) {
    if ((corners[k] - detection->corners[k]).norm() > o.max_correction_px) return false;
  }
  detection->corners = corners;
  return true;
}

}  // namespace calibench
