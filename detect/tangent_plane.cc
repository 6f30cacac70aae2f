#include "detect/tangent_plane.h"

#include <Eigen/Geometry>
#include <cmath>

namespace calibench {

bool TangentPlane::About(const Eigen::Vector3d& ray, TangentPlane* plane) {
  const double n = ray.norm();
  if (!(n > 0) || !std::isfinite(n)) return false;
  TangentPlane p;
  p.c = ray / n;
  constexpr double kNearY = 0.9;  // |c_y| above this: Y x c is short; the basis starts from X.
  if (std::abs(p.c.y()) < kNearY) {
    p.e1 = Eigen::Vector3d::UnitY().cross(p.c).normalized();
    p.e2 = p.c.cross(p.e1);
  } else {
    p.e2 = p.c.cross(Eigen::Vector3d::UnitX()).normalized();
    p.e1 = p.e2.cross(p.c);
  }
  *plane = p;
  return true;
}

bool TangentPlane::AboutPixels(const CameraIntrinsics& camera,
                               const std::array<Eigen::Vector2d, 4>& pixels, TangentPlane* plane,
                               std::array<Eigen::Vector2d, 4>* on_plane) {
  std::array<Eigen::Vector3d, 4> rays;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    if (!UnprojectToRay(camera, pixels[k], &rays[k])) return false;
    sum += rays[k];
  }
  if (!About(sum, plane)) return false;
  for (int k = 0; k < 4; ++k) {
    if (!plane->FromRay(rays[k], &(*on_plane)[k])) return false;
  }
  return true;
}

bool TangentPlane::FromRay(const Eigen::Vector3d& ray, Eigen::Vector2d* q) const {
  const double w = c.dot(ray);
  if (!(w > 1e-9 * ray.norm())) return false;
  *q = Eigen::Vector2d(e1.dot(ray), e2.dot(ray)) / w;
  return true;
}

bool TangentPlane::FromPixel(const CameraIntrinsics& camera, const Eigen::Vector2d& pixel,
                             Eigen::Vector2d* q) const {
  Eigen::Vector3d ray;
  return UnprojectToRay(camera, pixel, &ray) && FromRay(ray, q);
}

bool TangentPlane::ToPixel(const CameraIntrinsics& camera, const Eigen::Vector2d& q,
                           Eigen::Vector2d* pixel) const {
  return ProjectPoint(camera, ToRay(q), pixel);
}

}  // namespace calibench
