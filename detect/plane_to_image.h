// A plane's points mapped to pixels, fitted to point pairs: a board's coordinates (tag edges) or a
// single tag's ([0, 1]^2 its black square). It is what paints Kalibr's corner squares next to a
// found tag and predicts the tags the detector missed (frame_detector.h).
//
// Without a lens (camera nullptr or undistorted) the map is the homography H from the plane to
// the image, pixel = hnormalized(H (x, y, 1)). With a distorted camera the plane is mapped by a
// homography onto the tangent plane about the pairs' mean ray (detect/tangent_plane.h) and the
// point's ray e1 h_x + e2 h_y + c h_w is projected by the lens: the plane's straight lines bend as
// the lens bends them, past 90 degrees from the axis too. The sign of w is taken from the first
// pair (a plane point past the tangent plane's horizon keeps its direction).
// Four pairs fix H exactly (cv::getPerspectiveTransform, on float coordinates); more are fitted by
// least squares (cv::findHomography, no outlier rejection).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "camera/camera.h"
#include "detect/tangent_plane.h"

namespace calibench {

class PlaneToImage {
 public:
  // False (map unusable) for fewer than 4 pairs, sizes that differ, a pixel without a ray
  // through the lens or in front of the tangent plane, or a degenerate configuration.
  bool Fit(const CameraIntrinsics* camera, const std::vector<Eigen::Vector2d>& on_plane,
           const std::vector<Eigen::Vector2d>& pixels);
  // The pixel of a plane point; false off the lens's valid region, or without a lens past the
  // image's horizon (w of the other sign than the first pair's).
  bool operator()(const Eigen::Vector2d& on_plane, Eigen::Vector2d* pixel) const;

 private:
  const CameraIntrinsics* camera_ = nullptr;                // Distorted, or nullptr.
  Eigen::Matrix3d to_image_ = Eigen::Matrix3d::Identity();  // Plane -> image (or tangent plane).
  TangentPlane plane_;
  double w_sign_ = 1;
};

}  // namespace calibench
