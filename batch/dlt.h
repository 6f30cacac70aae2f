// Normalised (Hartley) direct linear transform of a constant 3x4 projection matrix M from
// correspondences (X_i, p_i) pooled over frames, then its decomposition into A (with skew), R, t
// (camera/projection_matrix.h; cheirality fixes the sign).
//
//   Normalise: X' = T3 X (centroid at 0, mean distance sqrt(3)), p' = T2 p (mean distance sqrt(2)).
//   Each correspondence gives two rows of  [ X'^T  0  -u' X'^T ; 0  X'^T  -v' X'^T ] m = 0;
//   m = right singular vector of the smallest singular value; M = T2^-1 M' T3.
//
// Degenerate input is a failed status, never a number: fewer than 6 correspondences, pooled points
// (nearly) coplanar or collinear, or a null space of dimension > 1.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "camera/projection_matrix.h"
#include "util/status.h"

namespace calibench {

struct DltOptions {
  // Pooled points count as coplanar when the smallest singular value of their centred scatter is
  // below this fraction of the largest (noise-free coplanar points give ~1e-16).
  double min_planarity_ratio = 1e-6;
  bool Check(std::string* why) const;
};

struct DltResult : MethodSummary {
  Matrix34d m = Matrix34d::Zero();  // Scaled so that the third row of its 3x3 block has unit norm.
  DecomposedCamera camera;
};

DltResult EstimateDlt(const std::vector<Eigen::Vector3d>& points,
                      const std::vector<Eigen::Vector2d>& pixels, const DltOptions& options = {});

}  // namespace calibench
