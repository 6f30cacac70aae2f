#include "batch/dlt.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

namespace calibench {

bool DltOptions::Check(std::string* why) const {
  if (min_planarity_ratio >= 0 && min_planarity_ratio < 1) return true;
  if (why) *why = "min_planarity_ratio must lie in [0, 1)";
  return false;
}

namespace {

long DistinctPoints(const std::vector<Eigen::Vector3d>& points) {
  std::vector<std::array<double, 3>> distinct;
  distinct.reserve(points.size());
  for (const Eigen::Vector3d& p : points) distinct.push_back({p.x(), p.y(), p.z()});
  std::sort(distinct.begin(), distinct.end());
  return std::unique(distinct.begin(), distinct.end()) - distinct.begin();
}

// Hartley's normalisation: x' = s3 (X - centroid), p' = s2 (p - pixel_centroid), as T3 (4x4) and
// T2 (3x3); spread: the singular values of the points' scatter (planarity).
struct Normalisation {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector2d pixel_centroid = Eigen::Vector2d::Zero();
  double s3 = 1, s2 = 1;
  Eigen::Matrix4d t3 = Eigen::Matrix4d::Identity();
  Eigen::Matrix3d t2 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();
  bool pixels_coincide = false;  // Then s2, t2 are not set.
};
void Normalise(const std::vector<Eigen::Vector3d>& points,
               const std::vector<Eigen::Vector2d>& pixels, Normalisation* out) {
  const int n = static_cast<int>(points.size());
  Eigen::Vector3d& centroid = out->centroid;
  Eigen::Vector2d& pixel_centroid = out->pixel_centroid;
  for (int i = 0; i < n; ++i) centroid += points[i], pixel_centroid += pixels[i];
  centroid /= n;
  pixel_centroid /= n;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double mean_dist = 0.0, pixel_mean_dist = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = points[i] - centroid;
    scatter += d * d.transpose();
    mean_dist += d.norm();
    pixel_mean_dist += (pixels[i] - pixel_centroid).norm();
  }
  mean_dist /= n;
  pixel_mean_dist /= n;
  // The scatter is symmetric positive semi-definite: its singular values are its eigenvalues
  // (descending, rounding's negatives at 0).
  const Eigen::Vector3d ascending =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter, Eigen::EigenvaluesOnly).eigenvalues();
  out->spread = ascending.reverse().cwiseMax(0.0);
  out->pixels_coincide = !(pixel_mean_dist > 0);
  if (out->pixels_coincide) return;
  out->s3 = std::sqrt(3.0) / mean_dist;
  out->s2 = std::sqrt(2.0) / pixel_mean_dist;
  out->t3.topLeftCorner<3, 3>() *= out->s3;
  out->t3.topRightCorner<3, 1>() = -out->s3 * centroid;
  out->t2.topLeftCorner<2, 2>() *= out->s2;
  out->t2.topRightCorner<2, 1>() = -out->s2 * pixel_centroid;
}

}  // namespace

DltResult EstimateDlt(const std::vector<Eigen::Vector3d>& points,
                      const std::vector<Eigen::Vector2d>& pixels, const DltOptions& options) {
  const SummaryClock clock;
  DltResult result;
  auto finish = [&](MethodStatus status, const std::string& message) {
    return clock.Finish(&result, status, message);
  };
  std::string why;
  if (!options.Check(&why)) return finish(MethodStatus::kFailed, "dlt options: " + why);
  const int n = static_cast<int>(points.size());
  if (n != static_cast<int>(pixels.size())) {
    return finish(MethodStatus::kFailed, "points and pixels differ in number");
  }
  if (n < 6) {
    return finish(MethodStatus::kFailed,
                  "the DLT needs at least 6 correspondences, got " + std::to_string(n));
  }
  // Repeated views of the same points (a static scene pooled over frames) add no constraint.
  if (const long count = DistinctPoints(points); count < 6) {
    return finish(MethodStatus::kFailed, "the DLT needs at least 6 distinct points, got " +
                                             std::to_string(count) + " (in " + std::to_string(n) +
                                             " correspondences)");
  }
  // Normalisation: each set centred and scaled to a mean distance of sqrt 3 (points) and
  // sqrt 2 (pixels).
  Normalisation norm;
  Normalise(points, pixels, &norm);
  if (!(norm.spread[0] > 0) ||
      std::sqrt(norm.spread[2] / norm.spread[0]) < options.min_planarity_ratio) {
    return finish(MethodStatus::kFailed,
                  "pooled points are coplanar or collinear: the DLT of a 3x4 matrix needs "
                  "non-coplanar points (use zhang for a planar target)");
  }
  if (norm.pixels_coincide) return finish(MethodStatus::kFailed, "all pixels coincide");
  const double s3 = norm.s3, s2 = norm.s2;
  const Eigen::Vector3d& centroid = norm.centroid;
  const Eigen::Vector2d& pixel_centroid = norm.pixel_centroid;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 12);
  for (int i = 0; i < n; ++i) {
    const Eigen::RowVector4d x = (s3 * (points[i] - centroid)).homogeneous().transpose();
    const Eigen::Vector2d p = s2 * (pixels[i] - pixel_centroid);
    a.block<1, 4>(2 * i, 0) = x;
    a.block<1, 4>(2 * i, 8) = -p.x() * x;
    a.block<1, 4>(2 * i + 1, 4) = x;
    a.block<1, 4>(2 * i + 1, 8) = -p.y() * x;
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  if (!(sv[10] > 1e-12 * sv[0])) {
    return finish(MethodStatus::kFailed, "degenerate configuration: the DLT null space is not 1-D");
  }
  const Eigen::VectorXd m_vec = svd.matrixV().col(11);
  Matrix34d m_norm;
  m_norm << m_vec.segment<4>(0).transpose(), m_vec.segment<4>(4).transpose(),
      m_vec.segment<4>(8).transpose();
  Matrix34d m = norm.t2.inverse() * m_norm * norm.t3;
  m /= m.block<1, 3>(2, 0).norm();
  result.m = m;
  if (!DecomposeProjectionMatrix(m, points, &result.camera, &why)) {
    return finish(MethodStatus::kFailed, "decomposition: " + why);
  }
  if (result.camera.lambda < 0) result.m = -m;
  result.iterations = 1;
  return finish(MethodStatus::kOk, "");
}

}  // namespace calibench
