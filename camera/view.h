// A view: known 3D points with their measured pixels, what every batch method consumes. Each
// view's points are expressed in that view's object frame: the board frame (planar target, z = 0)
// for per-view poses, or the parent frame P of a scenario (x_bar) when one pose serves all views.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace calibench {

struct View {
  std::vector<Eigen::Vector3d> points;  // point_in_object.
  std::vector<Eigen::Vector2d> pixels;  // Measured, pixel-centre convention of camera/camera.h.
};

}  // namespace calibench
