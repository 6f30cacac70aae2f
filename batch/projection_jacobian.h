// ProjectLens (camera/camera.h) with hand-written Jacobians, for every lens family: the hot path of
// the batch refinement (batch/reprojection_error.h). Same pixel, same valid region (false exactly
// where ProjectLens is), derivatives checked against ceres::Jet in tests/batch/refine_test.cc.
//
// Every family is pixel = A(g(P; lens)), P = point_in_cam, lens = the raw slots 5..9. The pinhole
// step A (slots 0..4) is shared:
//     u = fku (xd - yd cot(phi)) + u0,   v = fkv yd / sin(phi) + v0,
// and each family's lens step g gives (xd, yd) with d(xd, yd)/dP (2 x 3) and d(xd, yd)/d lens
// (2 x 5); then d pixel/dP = D g_P and d pixel/d lens = D g_lens, D = d(u, v)/d(xd, yd).
//
//   radtan:       n = (X, Y)/Z, g = radtan(n):  g_P = radtan'(n) [1/Z 0 -x/Z; 0 1/Z -y/Z].
//   equidistant:  n as radtan, r = |n|, theta = atan r, s = theta_d / r:
//                 d g/d n = s I + c n n^T,  c = (theta_d'(theta) / (1 + r^2) - s) / r^2,
//                 d g/d k_i = theta^(2i+1) n / r  (g = n, derivatives 0 on the axis, r^2 < 1e-24).
//   unified:      m = (X, Y)/den, den = Z + xi |P|, g = radtan(m) (k3 = 0):
//                 d m/dP = ([I 0] - m dden/dP) / den,  dden/dP = xi P^T/|P| + e_z^T,
//                 d m/d xi = -m |P| / den.
//   eucm:         d = sqrt(beta (X^2 + Y^2) + Z^2), den = alpha d + (1 - alpha) Z, g = (X, Y)/den:
//                 d g/dP = ([I 0] - g dden/dP) / den,  dden/dP = alpha (beta X, beta Y, Z)/d
//                 + (1 - alpha) e_z^T;  d g/d alpha = -g (d - Z)/den,
//                 d g/d beta = -g alpha (X^2 + Y^2) / (2 d den).
//   double-sphere: d1 = |P|, k = xi d1 + Z, d2 = |(X, Y, k)|, den = alpha d2 + (1 - alpha) k:
//                 dk/dP = xi P^T/d1 + e_z^T, dd2/dP = ((X, Y, 0) + k dk/dP)/d2,
//                 dden/dP = alpha dd2/dP + (1 - alpha) dk/dP;  dden/d xi = d1 (alpha k/d2 + 1 -
//                 alpha), dden/d alpha = d2 - k;  g and its derivatives as eucm's.
//
// Example:
//   ProjectionJacobian j;
//   if (ProjectWithJacobian(k.family, k.Params().data(), point_in_cam, true, &j)) use(j.pixel);
#pragma once

#include <Eigen/Core>

#include "camera/camera.h"

namespace calibench {

struct ProjectionJacobian {
  Eigen::Vector2d pixel;
  Eigen::Matrix<double, 2, 3> d_point;  // d pixel / d point_in_cam.
  // d pixel / d intrinsics in the raw order (phi in radians); unused slots 0.
  Eigen::Matrix<double, 2, PinholeSkewCamera::kNumParams, Eigen::RowMajor> d_intrinsics;
};

// The lens step of one family (slots 5..9 of `intrinsics`; see the header comment).
struct LensStep {
  double xd = 0, yd = 0;
  Eigen::Matrix<double, 2, 3> d_point;
  Eigen::Matrix<double, 2, 5> d_lens;
};
// Fills *step (Jacobians only if `jacobians`); false, as ProjectLens, outside the valid region.
using LensStepFunction = bool (*)(const double* intrinsics, const Eigen::Vector3d& point_in_cam,
                                  bool jacobians, LensStep* step);
// The family's step: chosen once per batch of points, not per point.
LensStepFunction LensStepOf(LensFamily family);

// The pinhole step's constants of one parameter block (sin and cos of phi, computed once).
struct PinholeStep {
  explicit PinholeStep(const double* intrinsics);
  const double* k;
  double sin_phi, cos_phi, cot_phi;
  Eigen::Matrix2d d_distorted;  // d(u, v) / d(xd, yd).
};

// pixel = A(step); with `jacobians`, out->d_point and out->d_intrinsics too.
void ApplyPinholeStep(const PinholeStep& pinhole, const LensStep& step, bool jacobians,
                      ProjectionJacobian* out);

// The whole projection (both steps). False exactly where ProjectLens is.
bool ProjectWithJacobian(LensFamily family, const double* intrinsics,
                         const Eigen::Vector3d& point_in_cam, bool jacobians,
                         ProjectionJacobian* out);

}  // namespace calibench
