// Projection uncertainty (batch/projection_uncertainty.h).
#include "batch/projection_uncertainty.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "batch/projection_jacobian.h"
#include "camera/estimate.h"

namespace calibench {

Eigen::Matrix<double, 6, 6> PoseTangentToFrameShare(const Rigid3& cam_from_board, int num_views) {
  // phi_v = 2 delta (EigenQuaternionManifold: q' = [sin|delta| delta/|delta|, cos|delta|] q);
  // eps_v = [t]x phi_v + dt.
  Eigen::Matrix<double, 6, 6> share = Eigen::Matrix<double, 6, 6>::Zero();
  share.topLeftCorner<3, 3>() = 2.0 * Eigen::Matrix3d::Identity();
  share.bottomLeftCorner<3, 3>() = 2.0 * Hat(cam_from_board.translation);
  share.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity();
  return share / static_cast<double>(std::max(1, num_views));
}

bool ProjectionCovarianceOfEstimate(const Eigen::MatrixXd& estimate_covariance,
                                    const Rigid3& cam_from_parent, ProjectionCovariance* out) {
  constexpr int kEstimateSize = CameraEstimate::kCovarianceSize;
  if (estimate_covariance.rows() != kEstimateSize || estimate_covariance.cols() != kEstimateSize ||
      !estimate_covariance.allFinite()) {
    return false;
  }
  Eigen::Matrix<double, ProjectionCovariance::kSize, kEstimateSize> l =
      Eigen::Matrix<double, ProjectionCovariance::kSize, kEstimateSize>::Zero();
  l.topLeftCorner<5, 5>().setIdentity();             // fku, fkv, phi (rad), u0, v0: raw slots 0..4.
  l.block<3, 3>(10, 5) = -cam_from_parent.rotation;  // phi_bar = -R_C^T delta.
  l.block<3, 3>(13, 8) = -cam_from_parent.rotation;  // eps = -R_C^T dx_C.
  out->covariance = l * estimate_covariance * l.transpose();
  out->sigma_px = 0.0;
  out->num_views = 1;
  return true;
}

double WorstStdPx(const Eigen::Matrix2d& covariance_px2) {
  return std::sqrt(std::max(
      0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance_px2).eigenvalues()[1]));
}

Eigen::Matrix2d SampleCovariancePx2(const std::vector<Eigen::Vector2d>& pixels) {
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  if (pixels.size() < 2) return cov;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& q : pixels) mean += q;
  mean /= static_cast<double>(pixels.size());
  for (const Eigen::Vector2d& q : pixels) cov += (q - mean) * (q - mean).transpose();
  return cov / static_cast<double>(pixels.size() - 1);
}

namespace {

// The ellipse of a 2 x 2 pixel covariance.
bool FillEllipse(PixelUncertainty* out, std::string* why) {
  if (!out->covariance_px2.allFinite()) {
    if (why) *why = "the covariance or the projection's derivatives are not finite there";
    return false;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(out->covariance_px2);  // Ascending.
  out->worst_std_px = std::sqrt(std::max(0.0, eig.eigenvalues()[1]));
  out->smallest_std_px = std::sqrt(std::max(0.0, eig.eigenvalues()[0]));
  const Eigen::Vector2d major = eig.eigenvectors().col(1);
  out->major_angle_rad = std::atan2(major.y(), major.x());
  return true;
}

}  // namespace

bool ProjectionUncertaintyAt(const CameraIntrinsics& camera, const ProjectionCovariance& covariance,
                             const Eigen::Vector2d& pixel, double distance_m, PixelUncertainty* out,
                             std::string* why) {
  if (!covariance.IsSet()) {
    if (why) *why = "no projection covariance (the calibration did not compute one)";
    return false;
  }
  if (!(distance_m > 0)) {
    if (why) *why = "distance must be positive (or infinity)";
    return false;
  }
  Eigen::Vector3d ray;
  if (!UnprojectToRay(camera, pixel, &ray)) {
    if (why) *why = "the pixel does not unproject (outside the lens's field)";
    return false;
  }
  const bool at_infinity = std::isinf(distance_m);
  const Eigen::Vector3d point = at_infinity ? ray : Eigen::Vector3d(distance_m * ray);
  const auto params = camera.Params();
  ProjectionJacobian jacobian;
  if (!ProjectWithJacobian(camera.family, params.data(), point, /*jacobians=*/true, &jacobian)) {
    if (why) *why = "the unprojected ray does not project back";
    return false;
  }
  Eigen::Matrix<double, 2, ProjectionCovariance::kSize> g;
  g.leftCols<10>() = jacobian.d_intrinsics;
  g.block<2, 3>(0, 10) = -jacobian.d_point * Hat(point);
  g.rightCols<3>() = at_infinity ? Eigen::Matrix<double, 2, 3>::Zero() : jacobian.d_point;
  out->covariance_px2 = g * covariance.covariance * g.transpose();
  return FillEllipse(out, why);
}

namespace {

// The point at `distance_m` along camera 0's ray through pixel0, in camera c (`turned`: its
// rotated part, R d u).
bool TransferredPoint(const CameraIntrinsics& camera0, const Rigid3& cam_c_from_cam_0,
                      const Eigen::Vector2d& pixel0, double distance_m, Eigen::Vector3d* turned,
                      Eigen::Vector3d* point) {
  Eigen::Vector3d ray;
  if (!(distance_m > 0) || !UnprojectToRay(camera0, pixel0, &ray)) return false;
  const bool at_infinity = std::isinf(distance_m);
  *turned = cam_c_from_cam_0.rotation * ((at_infinity ? 1.0 : distance_m) * ray);
  *point = *turned + (at_infinity ? Eigen::Vector3d::Zero() : cam_c_from_cam_0.translation);
  return true;
}

}  // namespace

bool TransferPixel(const CameraIntrinsics& camera0, const CameraIntrinsics& camera_c,
                   const Rigid3& cam_c_from_cam_0, const Eigen::Vector2d& pixel0, double distance_m,
                   Eigen::Vector2d* pixel_c) {
  Eigen::Vector3d turned, point;
  return TransferredPoint(camera0, cam_c_from_cam_0, pixel0, distance_m, &turned, &point) &&
         ProjectPoint(camera_c, point, pixel_c);
}

bool TransferUncertaintyAt(const CameraIntrinsics& camera0, const CameraIntrinsics& camera_c,
                           const Rigid3& cam_c_from_cam_0, const TransferCovariance& covariance,
                           const Eigen::Vector2d& pixel0, double distance_m, PixelUncertainty* out,
                           Eigen::Vector2d* pixel_c, std::string* why) {
  if (!covariance.IsSet()) {
    if (why) *why = "no relative-pose covariance (the rig solve did not compute one)";
    return false;
  }
  if (!(distance_m > 0)) {
    if (why) *why = "distance must be positive (or infinity)";
    return false;
  }
  const bool at_infinity = std::isinf(distance_m);
  const double range = at_infinity ? 1.0 : distance_m;
  Eigen::Vector3d turned, point;
  if (!TransferredPoint(camera0, cam_c_from_cam_0, pixel0, distance_m, &turned, &point)) {
    if (why) *why = "the pixel does not unproject through camera 0";
    return false;
  }
  const Eigen::Matrix3d& r = cam_c_from_cam_0.rotation;
  const auto params_c = camera_c.Params();
  ProjectionJacobian jacobian;
  if (!ProjectWithJacobian(camera_c.family, params_c.data(), point, /*jacobians=*/true,
                           &jacobian)) {
    if (why) *why = "the point does not project into camera c";
    return false;
  }
  if (pixel_c != nullptr) *pixel_c = jacobian.pixel;
  Eigen::Matrix<double, 2, TransferCovariance::kSize> g =
      Eigen::Matrix<double, 2, TransferCovariance::kSize>::Zero();
  // Camera 0's intrinsics move the ray: central differences (UnprojectToRay converges to 1e-12).
  auto params0 = camera0.Params();
  for (int i = 0; i < 10; ++i) {
    if (covariance.covariance(i, i) == 0) continue;  // Fixed or unused: no variance to carry.
    const double h = 1e-6 * std::max(1.0, std::abs(params0[i]));
    auto plus = params0, minus = params0;
    plus[i] += h, minus[i] -= h;
    Eigen::Vector3d ray_plus, ray_minus;
    if (!UnprojectToRay(CameraIntrinsics::FromParams(plus.data(), camera0.family), pixel0,
                        &ray_plus) ||
        !UnprojectToRay(CameraIntrinsics::FromParams(minus.data(), camera0.family), pixel0,
                        &ray_minus)) {
      continue;  // A parameter the lens cannot move there (its bound): no derivative.
    }
    g.col(i) = jacobian.d_point * r * (range * (ray_plus - ray_minus) / (2 * h));
  }
  g.block<2, 10>(0, 10) = jacobian.d_intrinsics;
  g.block<2, 3>(0, 20) = -jacobian.d_point * Hat(turned);
  g.block<2, 3>(0, 23) = at_infinity ? Eigen::Matrix<double, 2, 3>::Zero() : jacobian.d_point;
  out->covariance_px2 = g * covariance.covariance * g.transpose();
  return FillEllipse(out, why);
}

void SummariseUncertaintyMap(UncertaintyMap* map) {
  const ImageGrid& grid = map->worst_std_px;
  std::vector<double> finite;
  for (double v : grid.values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  map->median_px = map->max_px = map->centre_px = nan;
  if (finite.empty()) return;
  std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
  map->median_px = finite[finite.size() / 2];
  map->max_px = *std::max_element(finite.begin(), finite.end());
  map->centre_px = grid.At(grid.cols / 2, grid.rows / 2);
}

UncertaintyMap ProjectionUncertaintyMap(const CameraIntrinsics& camera,
                                        const ProjectionCovariance& covariance, int image_width,
                                        int image_height, const UncertaintyMapOptions& options) {
  UncertaintyMap map;
  map.worst_std_px = ImageGrid::Over(image_width, image_height, options.cols);
  ImageGrid& grid = map.worst_std_px;
  for (int j = 0; j < grid.rows; ++j) {
    for (int i = 0; i < grid.cols; ++i) {
      PixelUncertainty u;
      if (ProjectionUncertaintyAt(camera, covariance, grid.PixelAt(i, j), options.distance_m, &u,
                                  nullptr)) {
        grid.At(i, j) = u.worst_std_px;
      }
    }
  }
  SummariseUncertaintyMap(&map);
  return map;
}

UncertaintyMap TransferUncertaintyMap(const RigCamera& zero, const RigCamera& camera_c,
                                      const Rigid3& cam_c_from_cam_0,
                                      const TransferCovariance& covariance,
                                      const UncertaintyMapOptions& options) {
  UncertaintyMap map;
  map.worst_std_px = ImageGrid::Over(zero.image_width, zero.image_height, options.cols);
  ImageGrid& grid = map.worst_std_px;
  for (int j = 0; j < grid.rows; ++j) {
    for (int i = 0; i < grid.cols; ++i) {
      PixelUncertainty u;
      Eigen::Vector2d at;
      if (TransferUncertaintyAt(zero.intrinsics, camera_c.intrinsics, cam_c_from_cam_0, covariance,
                                grid.PixelAt(i, j), options.distance_m, &u, &at, nullptr) &&
          at.x() >= 0 && at.y() >= 0 && at.x() <= camera_c.image_width - 1 &&
          at.y() <= camera_c.image_height - 1) {
        grid.At(i, j) = u.worst_std_px;
      }
    }
  }
  SummariseUncertaintyMap(&map);
  return map;
}

bool ReprojectThroughEstimate(const CameraIntrinsics& reference, const CameraIntrinsics& estimate,
                              const std::vector<Rigid3>& reference_cam_from_board,
                              const std::vector<Rigid3>& estimate_cam_from_board,
                              const Eigen::Vector2d& pixel, double distance_m,
                              Eigen::Vector2d* reprojected) {
  if (reference_cam_from_board.empty() ||
      reference_cam_from_board.size() != estimate_cam_from_board.size()) {
    return false;
  }
  Eigen::Vector3d ray;
  if (!UnprojectToRay(reference, pixel, &ray)) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  const bool at_infinity = std::isinf(distance_m);
  for (size_t v = 0; v < reference_cam_from_board.size(); ++v) {
    const Rigid3& r = reference_cam_from_board[v];
    const Rigid3& e = estimate_cam_from_board[v];
    // A ray: the rotation alone (the point's scale does not change its projection).
    mean += at_infinity ? Eigen::Vector3d(e.rotation * r.rotation.transpose() * ray)
                        : Eigen::Vector3d(e.rotation * r.rotation.transpose() *
                                              (distance_m * ray - r.translation) +
                                          e.translation);
  }
  return ProjectPoint(estimate, mean / static_cast<double>(reference_cam_from_board.size()),
                      reprojected);
}

}  // namespace calibench
