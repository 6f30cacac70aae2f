#include "batch/projection_jacobian.h"

#include <cmath>
#include <stdexcept>

namespace calibench {
namespace {

using Matrix23 = Eigen::Matrix<double, 2, 3>;

// OpenCV's radtan of n = (x, y) (k1, k2, p1, p2, k3), with d(xd, yd)/dn and the 2 x 5 derivative
// in the order k1, k2, p1, p2, k3.
struct RadTanStep {
  double xd, yd;
  Eigen::Matrix2d d_n;
  Eigen::Matrix<double, 2, 5> d_k;
};
void RadTan(const double* k, double x, double y, bool jacobians, RadTanStep* out) {
  const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
  const double r2 = x * x + y * y, xy = x * y;
  const double d = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  out->xd = d * x + 2.0 * p1 * xy + p2 * (r2 + 2.0 * x * x);
  out->yd = d * y + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * xy;
  if (!jacobians) return;
  out->d_n = RadTanJacobian(k1, k2, p1, p2, k3, x, y);
  const double r4 = r2 * r2;
  out->d_k << x * r2, x * r4, 2.0 * xy, r2 + 2.0 * x * x, x * r4 * r2,  //
      y * r2, y * r4, r2 + 2.0 * y * y, 2.0 * xy, y * r4 * r2;
}

// d(X/Z, Y/Z)/dP.
Matrix23 PerspectiveJacobian(const Eigen::Vector3d& p) {
  const double inv_z = 1.0 / p.z();
  Matrix23 j;
  j << inv_z, 0.0, -p.x() * inv_z * inv_z, 0.0, inv_z, -p.y() * inv_z * inv_z;
  return j;
}

// d((X, Y)/den)/dP = ([I 0] - g dden/dP) / den, for g = (X, Y)/den.
Matrix23 QuotientJacobian(double gx, double gy, double den, const Eigen::RowVector3d& dden_dp) {
  Matrix23 j = -Eigen::Vector2d(gx, gy) * dden_dp;
  j(0, 0) += 1.0;
  j(1, 1) += 1.0;
  return j / den;
}

bool RadTanLens(const double* intrinsics, const Eigen::Vector3d& p, bool jacobians,
                LensStep* step) {
  if (!(p.z() > 0)) return false;
  RadTanStep r;
  RadTan(intrinsics + 5, p.x() / p.z(), p.y() / p.z(), jacobians, &r);
  step->xd = r.xd;
  step->yd = r.yd;
  if (!jacobians) return true;
  step->d_point = r.d_n * PerspectiveJacobian(p);
  step->d_lens = r.d_k;
  return true;
}

bool EquidistantLens(const double* intrinsics, const Eigen::Vector3d& p, bool jacobians,
                     LensStep* step) {
  if (!(p.z() > 0)) return false;
  const double* k = intrinsics + 5;
  const double x = p.x() / p.z(), y = p.y() / p.z(), r2 = x * x + y * y;
  if (!(r2 > 1e-24)) {  // On the axis: g = n (ProjectLens's limit).
    step->xd = x, step->yd = y;
    if (!jacobians) return true;
    step->d_point = PerspectiveJacobian(p);
    step->d_lens.setZero();
    return true;
  }
  const double r = std::sqrt(r2), theta = std::atan(r), t2 = theta * theta;
  const double theta_d = theta * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
  const double s = theta_d / r;
  step->xd = s * x, step->yd = s * y;
  if (!jacobians) return true;
  const double slope = 1.0 + t2 * (3 * k[0] + t2 * (5 * k[1] + t2 * (7 * k[2] + t2 * 9 * k[3])));
  const double c = (slope / (1.0 + r2) - s) / r2;
  const Eigen::Vector2d n(x, y);
  const Eigen::Matrix2d dg_dn = s * Eigen::Matrix2d::Identity() + c * n * n.transpose();
  step->d_point = dg_dn * PerspectiveJacobian(p);
  double power = theta * t2 / r;  // theta^3 / r, then theta^5 / r, ...
  for (int i = 0; i < 4; ++i, power *= t2) step->d_lens.col(i) = power * n;
  step->d_lens.col(4).setZero();
  return true;
}

bool UnifiedLens(const double* intrinsics, const Eigen::Vector3d& p, bool jacobians,
                 LensStep* step) {
  const double xi = intrinsics[5];
  const double rho = p.norm();
  if (!UnifiedCamera::InRegion(xi, p.z(), rho)) return false;
  const double den = p.z() + xi * rho;
  const double mx = p.x() / den, my = p.y() / den;
  const double k[5] = {intrinsics[6], intrinsics[7], intrinsics[8], intrinsics[9], 0.0};
  RadTanStep r;
  RadTan(k, mx, my, jacobians, &r);
  step->xd = r.xd;
  step->yd = r.yd;
  if (!jacobians) return true;
  Eigen::RowVector3d dden_dp = (xi / rho) * p.transpose();
  dden_dp[2] += 1.0;
  step->d_point = r.d_n * QuotientJacobian(mx, my, den, dden_dp);
  step->d_lens.col(0) = r.d_n * (Eigen::Vector2d(mx, my) * (-rho / den));
  step->d_lens.rightCols<4>() = r.d_k.leftCols<4>();
  return true;
}

bool EucmLens(const double* intrinsics, const Eigen::Vector3d& p, bool jacobians, LensStep* step) {
  const double alpha = intrinsics[5], beta = intrinsics[6];
  const double xy2 = p.x() * p.x() + p.y() * p.y();
  const double d = std::sqrt(beta * xy2 + p.z() * p.z());
  if (!EucmCamera::InRegion(alpha, beta, p.z(), d)) return false;
  const double den = alpha * d + (1.0 - alpha) * p.z();
  step->xd = p.x() / den, step->yd = p.y() / den;
  if (!jacobians) return true;
  Eigen::RowVector3d dden_dp(alpha * beta * p.x() / d, alpha * beta * p.y() / d,
                             alpha * p.z() / d + 1.0 - alpha);
  step->d_point = QuotientJacobian(step->xd, step->yd, den, dden_dp);
  const Eigen::Vector2d g(step->xd, step->yd);
  step->d_lens.setZero();
  step->d_lens.col(0) = -g * ((d - p.z()) / den);
  step->d_lens.col(1) = -g * (alpha * xy2 / (2.0 * d * den));
  return true;
}

bool DoubleSphereLens(const double* intrinsics, const Eigen::Vector3d& p, bool jacobians,
                      LensStep* step) {
  const double xi = intrinsics[5], alpha = intrinsics[6];
  const double xy2 = p.x() * p.x() + p.y() * p.y();
  const double d1 = std::sqrt(xy2 + p.z() * p.z());
  if (!DoubleSphereCamera::InRegion(xi, alpha, p.z(), d1)) return false;
  const double k = xi * d1 + p.z();
  const double d2 = std::sqrt(xy2 + k * k);
  const double den = alpha * d2 + (1.0 - alpha) * k;
  step->xd = p.x() / den, step->yd = p.y() / den;
  if (!jacobians) return true;
  Eigen::RowVector3d dk_dp = (xi / d1) * p.transpose();
  dk_dp[2] += 1.0;
  const Eigen::RowVector3d dd2_dp = (Eigen::RowVector3d(p.x(), p.y(), 0.0) + k * dk_dp) / d2;
  const Eigen::RowVector3d dden_dp = alpha * dd2_dp + (1.0 - alpha) * dk_dp;
  step->d_point = QuotientJacobian(step->xd, step->yd, den, dden_dp);
  const Eigen::Vector2d g(step->xd, step->yd);
  step->d_lens.setZero();
  step->d_lens.col(0) = -g * (d1 * (alpha * k / d2 + 1.0 - alpha) / den);
  step->d_lens.col(1) = -g * ((d2 - k) / den);
  return true;
}

}  // namespace

LensStepFunction LensStepOf(LensFamily family) {
  switch (family) {
    case LensFamily::kRadTan:
      return RadTanLens;
    case LensFamily::kEquidistant:
      return EquidistantLens;
    case LensFamily::kUnified:
      return UnifiedLens;
    case LensFamily::kEucm:
      return EucmLens;
    case LensFamily::kDoubleSphere:
      return DoubleSphereLens;
  }
  throw std::invalid_argument("LensStepOf: not a LensFamily enumerator");
}

PinholeStep::PinholeStep(const double* intrinsics)
    : k(intrinsics),
      sin_phi(std::sin(intrinsics[2])),
      cos_phi(std::cos(intrinsics[2])),
      cot_phi(cos_phi / sin_phi) {
  d_distorted << k[0], -k[0] * cot_phi, 0.0, k[1] / sin_phi;
}

void ApplyPinholeStep(const PinholeStep& a, const LensStep& step, bool jacobians,
                      ProjectionJacobian* out) {
  const double* k = a.k;
  const double xd = step.xd, yd = step.yd;
  out->pixel = Eigen::Vector2d(k[0] * (xd - yd * a.cot_phi) + k[3], k[1] * yd / a.sin_phi + k[4]);
  if (!jacobians) return;
  out->d_point = a.d_distorted * step.d_point;
  auto& j = out->d_intrinsics;
  const double sin2 = a.sin_phi * a.sin_phi;
  j.leftCols<5>() << xd - yd * a.cot_phi, 0.0, k[0] * yd / sin2, 1.0, 0.0,  //
      0.0, yd / a.sin_phi, -k[1] * yd * a.cos_phi / sin2, 0.0, 1.0;
  j.rightCols<5>() = a.d_distorted * step.d_lens;
}

bool ProjectWithJacobian(LensFamily family, const double* intrinsics,
                         const Eigen::Vector3d& point_in_cam, bool jacobians,
                         ProjectionJacobian* out) {
  LensStep step;
  if (!LensStepOf(family)(intrinsics, point_in_cam, jacobians, &step)) return false;
  ApplyPinholeStep(PinholeStep(intrinsics), step, jacobians, out);
  return true;
}

}  // namespace calibench
