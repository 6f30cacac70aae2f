// The covariance a calibrated camera's projection uncertainty needs (batch/projection_uncertainty.h
// defines it and computes with it): a value a camera estimate and a camera file carry.
//
// z = [the 10 raw intrinsics of camera/camera.h (phi in radians; fixed ones 0), phi_bar (3, rad:
// the rotation of the camera frame, averaged over the views), eps (3, the target's unit: its
// translation)], so that a point p of the camera frame moves by -[p]x phi_bar + eps when the
// calibration is re-made.
#pragma once

#include <Eigen/Core>

namespace calibench {

struct ProjectionCovariance {
  static constexpr int kSize = 16;
  using Matrix = Eigen::Matrix<double, kSize, kSize>;
  // Cov(z), with sigma^2 included (px^2 for the pixels it maps to).
  Matrix covariance = Matrix::Zero();
  double sigma_px = 0.0;  // The per-coordinate pixel noise it was scaled by.
  int num_views = 0;      // Views averaged over (0: not computed).
  bool IsSet() const { return num_views > 0; }
};

}  // namespace calibench
