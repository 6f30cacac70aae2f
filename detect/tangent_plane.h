// A local gnomonic (tangent) plane about a ray: where a lens-aware fit draws a planar target, for
// any lens and any direction (past 90 deg from the optical axis too).
//
// With the centre ray c (unit) and an orthonormal basis (e1, e2, c), a ray r maps to
//     q = (e1 . r, e2 . r) / (c . r),
// the point where r meets the plane tangent to the unit sphere at c; rays with c . r > 0 only
// (the half-space of directions in front of the plane). Its inverse is the ray e1 q_x + e2 q_y + c.
// A plane in space (a board) is mapped to this plane by a homography (B^T [r1 r2 t] for
// B = [e1 e2 c] and cam_from_board = [R | t]): straight board edges stay straight, whatever the
// lens. The camera's undistorted normalised plane z = 1 is the tangent plane about c = (0, 0, 1),
// which cannot hold rays at or past 90 deg. Through a camera: pixel -> ray by UnprojectToRay, ray
// -> pixel by ProjectPoint (camera/camera.h).
//
// The basis: e1 along Y x c (the image's +u for c = +Z: the plane is the normalised plane there),
// e2 = c x e1; nearer the Y axis, e2 along c x X, e1 = e2 x c.
//
//   TangentPlane plane;
//   std::array<Eigen::Vector2d, 4> corners_on_plane;
//   if (TangentPlane::AboutPixels(camera, tag_corners, &plane, &corners_on_plane) &&
//       plane.FromPixel(camera, pixel, &q)) ...
#pragma once

#include <Eigen/Core>
#include <array>

#include "camera/camera.h"

namespace calibench {

struct TangentPlane {
  Eigen::Vector3d c = Eigen::Vector3d::UnitZ();  // The centre ray (unit).
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();

  // The plane about the direction of `ray` (any positive length); false for a zero or non-finite
  // ray.
  static bool About(const Eigen::Vector3d& ray, TangentPlane* plane);
  // The plane about the mean of the unit rays of `pixels` (e.g. a tag's four corners) through a
  // camera, and their points on it; false when a pixel has no ray (outside the lens's valid
  // region) or its ray is not in front of that plane.
  static bool AboutPixels(const CameraIntrinsics& camera,
                          const std::array<Eigen::Vector2d, 4>& pixels, TangentPlane* plane,
                          std::array<Eigen::Vector2d, 4>* on_plane);
  // q of ray r (any positive multiple); false unless c . r > 1e-9 |r| (in front of the plane).
  bool FromRay(const Eigen::Vector3d& ray, Eigen::Vector2d* q) const;
  // The ray through q (not unit): e1 q_x + e2 q_y + c.
  Eigen::Vector3d ToRay(const Eigen::Vector2d& q) const { return e1 * q.x() + e2 * q.y() + c; }
  // The ray of a homogeneous plane point (x, y, w): e1 x + e2 y + c w, the direction of the point
  // whatever the sign of w (w < 0: a ray behind the plane, e.g. a board point past its horizon).
  Eigen::Vector3d ToRayHomogeneous(const Eigen::Vector3d& h) const {
    return e1 * h.x() + e2 * h.y() + c * h.z();
  }
  // Through a camera: q of the pixel's ray (UnprojectToRay); false where the pixel has no ray or
  // its ray is not in front of the plane.
  bool FromPixel(const CameraIntrinsics& camera, const Eigen::Vector2d& pixel,
                 Eigen::Vector2d* q) const;
  // The pixel of q (ProjectPoint); false outside the lens's valid region.
  bool ToPixel(const CameraIntrinsics& camera, const Eigen::Vector2d& q,
               Eigen::Vector2d* pixel) const;
};

// How differently two cameras bend a quadrilateral's edges between the same four pixel corners
// (a tag's): the largest distance (px) from points of the edges drawn through `a` to the edges
// drawn through `b`, 7 points an edge. An edge through a camera is the image of the straight
// segment between its corners' points on the tangent plane about the mean of their rays; `a`
// nullptr draws straight edges (a homography in pixels). The distance is measured to a point of
// b's edge (the image of the foot of the perpendicular on b's plane): an upper bound of the
// distance between the curves. The lens-aware photometric fit (photometric_fit.h) depends on its
// camera only through this shape (pose, corners and blur are fitted), so corners fitted through
// `a` move by about this much when fitted again through `b`. NaN where a corner or a sample has
// no ray through a camera.
double EdgeBendChangePx(const CameraIntrinsics* a, const CameraIntrinsics& b,
                        const std::array<Eigen::Vector2d, 4>& corners);

}  // namespace calibench
