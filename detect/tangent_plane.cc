#include "detect/tangent_plane.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

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

namespace {

constexpr int kSamplesPerEdge = 7;  // At t = 1/8 .. 7/8 of the edge.

// The edges' sample points through `camera` (nullptr: straight), edge e from corner e to e + 1.
bool EdgeSamples(const CameraIntrinsics* camera, const std::array<Eigen::Vector2d, 4>& corners,
                 std::array<Eigen::Vector2d, 4 * kSamplesPerEdge>* samples) {
  TangentPlane plane;
  std::array<Eigen::Vector2d, 4> ends = corners;
  if (camera && !TangentPlane::AboutPixels(*camera, corners, &plane, &ends)) return false;
  for (int e = 0; e < 4; ++e) {
    for (int s = 0; s < kSamplesPerEdge; ++s) {
      const double t = (s + 1.0) / (kSamplesPerEdge + 1.0);
      const Eigen::Vector2d q = ends[e] + t * (ends[(e + 1) % 4] - ends[e]);
      Eigen::Vector2d& pixel = (*samples)[e * kSamplesPerEdge + s];
      if (!camera) {
        pixel = q;
      } else if (!plane.ToPixel(*camera, q, &pixel)) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

double EdgeBendChangePx(const CameraIntrinsics* a, const CameraIntrinsics& b,
                        const std::array<Eigen::Vector2d, 4>& corners) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::array<Eigen::Vector2d, 4 * kSamplesPerEdge> samples;
  TangentPlane plane;
  std::array<Eigen::Vector2d, 4> ends;
  if (!EdgeSamples(a, corners, &samples) || !TangentPlane::AboutPixels(b, corners, &plane, &ends)) {
    return kNaN;
  }
  double worst = 0;
  for (int e = 0; e < 4; ++e) {
    const Eigen::Vector2d q0 = ends[e], d = ends[(e + 1) % 4] - ends[e];
    if (!(d.squaredNorm() > 0)) return kNaN;
    for (int s = 0; s < kSamplesPerEdge; ++s) {
      const Eigen::Vector2d& pixel = samples[e * kSamplesPerEdge + s];
      Eigen::Vector2d q, foot_pixel;
      if (!plane.FromPixel(b, pixel, &q)) return kNaN;
      const double t = (q - q0).dot(d) / d.squaredNorm();
      if (!plane.ToPixel(b, q0 + t * d, &foot_pixel)) return kNaN;
      worst = std::max(worst, (pixel - foot_pixel).norm());
    }
  }
  return worst;
}

}  // namespace calibench
