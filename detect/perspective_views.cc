#include "detect/perspective_views.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The angle (rad) off the optical axis of the ray through `pixel`, or NaN without one.
double AngleOffAxis(const CameraIntrinsics& camera, const Eigen::Vector2d& pixel) {
  Eigen::Vector3d ray;
  if (!UnprojectToRay(camera, pixel, &ray)) return std::numeric_limits<double>::quiet_NaN();
  return std::acos(std::clamp(ray.normalized().z(), -1.0, 1.0));
}

// A rotation whose third column is `axis` (unit).
Eigen::Matrix3d LookingAlong(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d up =
      std::abs(axis.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x = up.cross(axis).normalized();
  const Eigen::Vector3d y = axis.cross(x);
  Eigen::Matrix3d r;
  r << x, y, axis;
  return r;
}

// The lens's angular resolution (px / rad) along `axis`: the mean of its radial scale (towards
// the optical axis and away) and its tangential one, by differences of the projection.
double PixelsPerRadian(const CameraIntrinsics& camera, const Eigen::Vector3d& axis) {
  constexpr double kStep = 1e-4;
  Eigen::Vector3d radial = Eigen::Vector3d::UnitZ() - axis.z() * axis;  // Towards the axis.
  radial = radial.norm() > 1e-9 ? radial.normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d tangential = axis.cross(radial);
  Eigen::Vector2d at, along_radial, along_tangential;
  if (!ProjectPoint(camera, axis, &at) ||
      !ProjectPoint(camera, axis + kStep * radial, &along_radial) ||
      !ProjectPoint(camera, axis + kStep * tangential, &along_tangential)) {
    return camera.fku_px;
  }
  return 0.5 * ((along_radial - at).norm() + (along_tangential - at).norm()) / kStep;
}

}  // namespace

Eigen::Vector3d PerspectiveView::RayOf(const Eigen::Vector2d& pixel) const {
  const double c = 0.5 * (size_px - 1);
  return cam_from_view * Eigen::Vector3d(pixel.x() - c, pixel.y() - c, focal_px);
}

std::vector<PerspectiveView> PerspectiveViewsCovering(const CameraIntrinsics& camera, int width,
                                                      int height, int max_side_px) {
  double theta_max = 0;
  constexpr int kBorderStep = 8;
  auto consider = [&](double x, double y) {
    const double angle = AngleOffAxis(camera, Eigen::Vector2d(x, y));
    if (std::isfinite(angle)) theta_max = std::max(theta_max, angle);
  };
  for (int x = 0; x < width; x += kBorderStep) consider(x, 0), consider(x, height - 1);
  for (int y = 0; y < height; y += kBorderStep) consider(0, y), consider(width - 1, y);
  // A lens whose valid region ends inside the image (an image circle): the border's rays may have
  // none; the rays along the axes from the centre out tell its reach.
  for (int x = 0; x < width; x += kBorderStep) consider(x, camera.v0_px);
  for (int y = 0; y < height; y += kBorderStep) consider(camera.u0_px, y);
  std::vector<PerspectiveView> views;
  if (theta_max < kMinWideHalfFieldDeg * kDeg) return views;
  std::vector<double> rings = {45 * kDeg};
  if (theta_max > 85 * kDeg) rings.push_back(theta_max - 35 * kDeg);
  std::vector<Eigen::Vector3d> axes = {Eigen::Vector3d::UnitZ()};
  for (size_t r = 0; r < rings.size(); ++r) {
    for (int k = 0; k < 8; ++k) {
      const double azimuth = (k + 0.5 * r) * 45 * kDeg;  // A second ring is staggered.
      axes.emplace_back(std::sin(rings[r]) * std::cos(azimuth),
                        std::sin(rings[r]) * std::sin(azimuth), std::cos(rings[r]));
    }
  }
  for (const Eigen::Vector3d& axis : axes) {
    PerspectiveView view;
    view.cam_from_view = LookingAlong(axis);
    view.focal_px = PixelsPerRadian(camera, axis);
    const double half_side = view.focal_px * std::tan(kViewHalfFieldDeg * kDeg);
    view.size_px = std::min(max_side_px, static_cast<int>(std::ceil(2 * half_side)) + 1);
    views.push_back(view);
  }
  return views;
}

bool ViewToImage(const CameraIntrinsics& camera, const PerspectiveView& view,
                 const Eigen::Vector2d& view_pixel, Eigen::Vector2d* image_pixel) {
  return ProjectPoint(camera, view.RayOf(view_pixel), image_pixel);
}

int ViewGrayRange(const GrayImageView& image, const CameraIntrinsics& camera,
                  const PerspectiveView& view, int step) {
  int lo = 255, hi = 0;
  for (int v = 0; v < view.size_px; v += step) {
    for (int u = 0; u < view.size_px; u += step) {
      Eigen::Vector2d p;
      if (!ViewToImage(camera, view, Eigen::Vector2d(u, v), &p)) continue;
      const long x = std::lround(p.x()), y = std::lround(p.y());
      if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
      const int g = image.at(static_cast<int>(x), static_cast<int>(y));
      lo = std::min(lo, g), hi = std::max(hi, g);
    }
  }
  return std::max(0, hi - lo);
}

GrayImage ResampleView(const GrayImageView& image, const CameraIntrinsics& camera,
                       const PerspectiveView& view) {
  GrayImage out;
  out.width = out.height = view.size_px;
  out.pixels.assign(static_cast<size_t>(view.size_px) * view.size_px, 128);
  for (int v = 0; v < view.size_px; ++v) {
    for (int u = 0; u < view.size_px; ++u) {
      Eigen::Vector2d p;
      if (!ViewToImage(camera, view, Eigen::Vector2d(u, v), &p)) continue;
      const int x0 = static_cast<int>(std::floor(p.x())), y0 = static_cast<int>(std::floor(p.y()));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= image.width || y0 + 1 >= image.height) continue;
      const double fx = p.x() - x0, fy = p.y() - y0;
      const double top = (1 - fx) * image.at(x0, y0) + fx * image.at(x0 + 1, y0);
      const double bottom = (1 - fx) * image.at(x0, y0 + 1) + fx * image.at(x0 + 1, y0 + 1);
      out.pixels[static_cast<size_t>(v) * view.size_px + u] =
          static_cast<uint8_t>(std::lround((1 - fy) * top + fy * bottom));
    }
  }
  return out;
}

}  // namespace calibench
