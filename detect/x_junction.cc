#include "detect/x_junction.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "detect/tangent_plane.h"
#include "sim/image_filters.h"

namespace calibench {
namespace {

// The reach of GaussianBlur's kernel for `sigma` px (3 sigma, whole pixels); 0 without blur.
int KernelReach(double sigma) { return sigma > 0 ? static_cast<int>(std::ceil(3 * sigma)) : 0; }

// Below this ratio of the smallest to the largest eigenvalue of sum w g g^T the gradients span
// one direction only (an edge, not a junction): q is then undetermined along the edge.
constexpr double kMinGradientSpread = 1e-3;

// Pixel -> the plane the junction is solved in (header comment): through a camera the tangent
// plane about the start's ray or the undistorted normalised plane, the image (relative to the
// start) without one.
struct LocalPlane {
  const CameraIntrinsics* camera = nullptr;
  bool normalized = false;  // The undistorted normalised plane z = 1 instead of a tangent plane.
  TangentPlane plane;
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();

  bool About(const Eigen::Vector2d& q_px) {
    centre_px = q_px;
    if (!camera || normalized) return true;
    Eigen::Vector3d ray;
    return UnprojectToRay(*camera, q_px, &ray) && TangentPlane::About(ray, &plane);
  }
  bool FromPixel(const Eigen::Vector2d& p, Eigen::Vector2d* t) const {
    if (!camera) {
      *t = p - centre_px;
      return true;
    }
    if (normalized) return UnprojectPixel(*camera, p, t);
    return plane.FromPixel(*camera, p, t);
  }
  bool ToPixel(const Eigen::Vector2d& t, Eigen::Vector2d* p) const {
    if (!camera) {
      *p = centre_px + t;
      return true;
    }
    if (normalized) return ProjectPoint(*camera, Eigen::Vector3d(t.x(), t.y(), 1), p);
    return plane.ToPixel(*camera, t, p);
  }
  // dt/dp at pixel p by central differences over +-1 px; false where a point has no ray.
  bool JacobianAt(const Eigen::Vector2d& p, Eigen::Matrix2d* dt_dp) const {
    Eigen::Vector2d tx0, tx1, ty0, ty1;
    if (!FromPixel(p - Eigen::Vector2d(1, 0), &tx0) ||
        !FromPixel(p + Eigen::Vector2d(1, 0), &tx1) ||
        !FromPixel(p - Eigen::Vector2d(0, 1), &ty0) ||
        !FromPixel(p + Eigen::Vector2d(0, 1), &ty1)) {
      return false;
    }
    *dt_dp << (tx1 - tx0) / 2, (ty1 - ty0) / 2;
    return true;
  }
};

// How far pixel -> plane departs from an affine map over a window of radius r about q: the
// change of its Jacobian (central differences) across the window along x and along y, relative
// to the Jacobian at q (Frobenius norms); infinite where a point has no ray.
double Nonlinearity(const LocalPlane& local, const Eigen::Vector2d& q, double r) {
  Eigen::Matrix2d at_q, a, b, c, d;
  if (!local.JacobianAt(q, &at_q) || !local.JacobianAt(q - Eigen::Vector2d(r, 0), &a) ||
      !local.JacobianAt(q + Eigen::Vector2d(r, 0), &b) ||
      !local.JacobianAt(q - Eigen::Vector2d(0, r), &c) ||
      !local.JacobianAt(q + Eigen::Vector2d(0, r), &d) || !(at_q.norm() > 0)) {
    return std::numeric_limits<double>::infinity();
  }
  return ((b - a).norm() + (d - c).norm()) / at_q.norm();
}

// *patch = the w x h pixels from (x0, y0) of `image` blurred by a Gaussian of `sigma` px
// (GaussianBlur, sim/image_filters.h; none for sigma 0), read from a patch grown by the kernel's
// reach, which the caller keeps inside the image.
void SmoothPatch(const GrayImageView& image, double sigma, int x0, int y0, int w, int h,
                 std::vector<float>* patch) {
  const int k = KernelReach(sigma);
  const int gw = w + 2 * k, gh = h + 2 * k;
  std::vector<float> grown(static_cast<size_t>(gw) * gh);
  for (int j = 0; j < gh; ++j) {
    for (int i = 0; i < gw; ++i)
      grown[static_cast<size_t>(j) * gw + i] = image.at(x0 - k + i, y0 - k + j);
  }
  if (sigma > 0) GaussianBlur(sigma, gw, gh, {k, k + w, k, k + h}, &grown);
  patch->resize(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j) {
    std::copy_n(grown.begin() + static_cast<ptrdiff_t>(j + k) * gw + k, w,
                patch->begin() + static_cast<ptrdiff_t>(j) * w);
  }
}

}  // namespace

bool XJunctionOptions::Check(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why) *why = reason;
    return false;
  };
  if (!(radius_px >= 2 && radius_px <= 50)) return fail("radius_px must be 2..50");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(tolerance_px > 0)) return fail("tolerance_px must be > 0");
  if (!(max_move_px > 0)) return fail("max_move_px must be > 0");
  if (!(gradient_sigma_px >= 0 && gradient_sigma_px <= 5))
    return fail("gradient_sigma_px must be 0..5");
  return true;
}

XJunctionSummary RefineXJunction(const GrayImageView& image, const CameraIntrinsics* camera,
                                 const XJunctionOptions& options, Eigen::Vector2d* corner) {
  XJunctionSummary summary;
  if (!options.Check(&summary.message)) return summary;
  const Eigen::Vector2d start = *corner;
  if (!start.allFinite()) {
    summary.message = "the start is not finite";
    return summary;
  }
  const double r = options.radius_px;
  LocalPlane local;
  local.camera = camera;
  if (!local.About(start)) {
    summary.message = "the estimate has no ray through the lens";
    return summary;
  }
  if (camera) {
    // The plane in which the image is nearest an affine map over the window (header comment).
    LocalPlane normalized = local;
    normalized.normalized = true;
    if (Nonlinearity(normalized, start, r) < Nonlinearity(local, start, r)) local = normalized;
  }
  // Pixels per plane unit at the start (the weights' scale: any fixed matrix keeps the window
  // point-symmetric).
  Eigen::Matrix2d dt_dp_at_start;
  if (!local.JacobianAt(start, &dt_dp_at_start)) {
    summary.message = "a pixel of the window has no ray through the lens";
    return summary;
  }
  const Eigen::Matrix2d px_per_t = dt_dp_at_start.inverse();
  const double area_at_start = std::abs(dt_dp_at_start.determinant());
  Eigen::Vector2d q = start;
  // The window's grid (plane points, smoothed pixels) and, per window pixel, the image gradient in
  // the plane and the pixel's plane area, kept while the window's bounds do not change.
  std::vector<Eigen::Vector2d> t, gradient_t;
  std::vector<float> smooth;
  std::vector<double> area;
  std::array<int, 4> grid_bounds = {0, -1, 0, -1};
  const int k = KernelReach(options.gradient_sigma_px);
  for (summary.iterations = 1; summary.iterations <= options.max_iterations; ++summary.iterations) {
    Eigen::Vector2d q_t;  // q in the plane.
    if (!local.FromPixel(q, &q_t)) {
      summary.message = "the estimate has no ray through the lens";
      return summary;
    }
    // Window pixels [x0, x1] x [y0, y1]; the grid of plane points has one ring more (for dt/dp),
    // and the gradients read one pixel beyond the window, of an image smoothed by a kernel of
    // half-width k.
    const int x0 = static_cast<int>(std::ceil(q.x() - r)),
              x1 = static_cast<int>(std::floor(q.x() + r));
    const int y0 = static_cast<int>(std::ceil(q.y() - r)),
              y1 = static_cast<int>(std::floor(q.y() + r));
    if (x0 < 1 + k || y0 < 1 + k || x1 > image.width - 2 - k || y1 > image.height - 2 - k) {
      summary.message = "the window leaves the image";
      return summary;
    }
    const int gw = x1 - x0 + 3, gh = y1 - y0 + 3;
    if (grid_bounds != std::array<int, 4>{x0, x1, y0, y1}) {
      grid_bounds = {x0, x1, y0, y1};
      gradient_t.clear();  // Computed again below, for the new window.
      SmoothPatch(image, options.gradient_sigma_px, x0 - 1, y0 - 1, gw, gh, &smooth);
      t.assign(static_cast<size_t>(gw) * gh, Eigen::Vector2d::Zero());
      for (int j = 0; j < gh; ++j) {
        for (int i = 0; i < gw; ++i) {
          if (!local.FromPixel(Eigen::Vector2d(x0 - 1 + i, y0 - 1 + j), &t[j * gw + i])) {
            summary.message = "a pixel of the window has no ray through the lens";
            return summary;
          }
        }
      }
    }
    auto t_at = [&](int x, int y) -> const Eigen::Vector2d& {
      return t[static_cast<size_t>(y - y0 + 1) * gw + (x - x0 + 1)];
    };
    const int ww = x1 - x0 + 1;  // Window pixel (x, y) is slot (y - y0) ww + (x - x0).
    if (gradient_t.empty()) {
      auto smooth_at = [&](int x, int y) {
        return smooth[static_cast<size_t>(y - y0 + 1) * gw + (x - x0 + 1)];
      };
      gradient_t.resize(static_cast<size_t>(ww) * (y1 - y0 + 1));
      area.resize(gradient_t.size());
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          Eigen::Matrix2d dt_dp;
          dt_dp << (t_at(x + 1, y) - t_at(x - 1, y)) / 2, (t_at(x, y + 1) - t_at(x, y - 1)) / 2;
          const Eigen::Vector2d g_px(0.5 * (smooth_at(x + 1, y) - smooth_at(x - 1, y)),
                                     0.5 * (smooth_at(x, y + 1) - smooth_at(x, y - 1)));
          // dI/dt = (dp/dt)^T dI/dp = (dt/dp)^-T dI/dp.
          const size_t slot = static_cast<size_t>(y - y0) * ww + (x - x0);
          gradient_t[slot] = dt_dp.transpose().partialPivLu().solve(g_px);
          area[slot] = std::abs(dt_dp.determinant());
        }
      }
    }
    Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d& tp = t_at(x, y);
        const double d2 = (px_per_t * (tp - q_t)).squaredNorm() / (r * r);
        if (d2 >= 1) continue;
        const size_t slot = static_cast<size_t>(y - y0) * ww + (x - x0);
        const Eigen::Vector2d& g = gradient_t[slot];
        const double w = (1 - d2) * (1 - d2) * area[slot] / area_at_start;
        const Eigen::Matrix2d ggt = w * g * g.transpose();
        a += ggt;
        b += ggt * tp;
      }
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(a);
    const double largest = eigen.eigenvalues()(1);
    summary.gradient_spread = largest > 0 ? eigen.eigenvalues()(0) / largest : 0.0;
    if (!(largest > 0) || !(eigen.eigenvalues()(0) > kMinGradientSpread * largest)) {
      summary.message = "no junction: the window's gradients do not span two directions";
      return summary;
    }
    Eigen::Vector2d next;
    if (!local.ToPixel(a.ldlt().solve(b), &next) || !next.allFinite()) {
      summary.message = "the estimate left the lens's valid region";
      return summary;
    }
    const double step = (next - q).norm();
    q = next;
    if ((q - start).norm() > options.max_move_px) {
      summary.message = "the estimate moved more than max_move_px from its start";
      return summary;
    }
    if (step < options.tolerance_px) {
      summary.converged = true;
      *corner = q;
      return summary;
    }
  }
  summary.iterations = options.max_iterations;
  summary.message = "did not settle within max_iterations";
  return summary;
}

}  // namespace calibench
