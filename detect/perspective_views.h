// Perspective views of a wide lens's image: where AprilTag 3 finds the tags a fisheye bends too
// much for it (a board near a 190 deg lens's image circle: its quads are curved, none decodes).
//
// A view is a virtual pinhole camera at the lens's centre, turned by `cam_from_view` (a rotation:
// the view's axis is its third column in the camera frame), with focal length focal_px and a
// square image of size_px; its pixel (u, v) (pixel centres at integers, camera.h) sees the ray
//     ray_in_cam = cam_from_view (u - c, v - c, focal_px)^T,  c = (size_px - 1) / 2,
// which the camera projects to an image pixel: the view's image is the camera's resampled there
// (bilinear). In a view straight board edges are straight again, and a tag's corners found in it
// map back through the same rays.
//
// The views that cover a lens (PerspectiveViewsCovering): its field's half-angle theta_max is the
// largest angle off the axis of a ray through the image's border (or the lens's valid region);
// below kMinWideHalfFieldDeg none are needed (an undistorted pinhole image already is one).
// Otherwise one view along the axis and a ring of eight about it at 45 deg off the axis, plus,
// past theta_max = 85 deg, a second ring (staggered) at theta_max - 35 deg; each view reaches
// kViewHalfFieldDeg from its axis to its sides. Every ray of the image then lies 10 deg or more
// inside some view (tested on a 190 deg lens whose image corners see 130 deg), so a tag (10-20
// deg across) lies whole in one. Each view's focal length is the lens's angular resolution
// (px / rad) along the view's axis: a tag keeps its size in pixels.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "camera/camera.h"
#include "sim/render.h"

namespace calibench {

constexpr double kMinWideHalfFieldDeg = 60.0;
constexpr double kViewHalfFieldDeg = 50.0;

struct PerspectiveView {
  Eigen::Matrix3d cam_from_view = Eigen::Matrix3d::Identity();
  double focal_px = 1.0;
  int size_px = 0;
  // The ray (camera frame, not unit) of view pixel `pixel`.
  Eigen::Vector3d RayOf(const Eigen::Vector2d& pixel) const;
};

// The views that cover the field of `camera` for images of width x height; empty when its
// half-field is below kMinWideHalfFieldDeg. Each view's side is at most max_side_px.
std::vector<PerspectiveView> PerspectiveViewsCovering(const CameraIntrinsics& camera, int width,
                                                      int height, int max_side_px = 1600);

// The view's image: `image` sampled bilinearly where the camera projects each view pixel's ray;
// pixels whose ray does not project into the image are mid gray (128).
GrayImage ResampleView(const GrayImageView& image, const CameraIntrinsics& camera,
                       const PerspectiveView& view);

// The range (max - min, gray levels) of `image` over the view's pixels on a grid of `step` px
// (nearest samples; a tag of 40 px holds ~100): whether the view may see anything to detect. A
// view over a flat background (a rendered frame without a board: its noise of 2 gray levels
// ranges over ~16) is not searched.
constexpr int kMinViewRangeGray = 48;
int ViewGrayRange(const GrayImageView& image, const CameraIntrinsics& camera,
                  const PerspectiveView& view, int step = 4);

// The image pixel that view pixel `view_pixel` sees; false when its ray does not project.
bool ViewToImage(const CameraIntrinsics& camera, const PerspectiveView& view,
                 const Eigen::Vector2d& view_pixel, Eigen::Vector2d* image_pixel);

}  // namespace calibench
