// Stereo rectification of two cameras of a rig (camera/rig.h), for every lens family: the
// rotations that make both image planes parallel to the baseline, a common pinhole for the
// rectified images, the remap tables, a side-by-side picture to check by eye, and the vertical
// disparity of co-observed corners (zero for a perfect calibration).
//
// Math (Bouguet's rectification, as cv::stereoRectify; a = first camera, b = second):
//   cam_b_from_cam_a = (R, T): p_b = R p_a + T (OpenCV's stereoCalibrate R, T).
//   r = Log(R); each camera turns half-way: r_half = Exp(-r / 2), so r_half R = r_half^T and
//   both cameras share the orientation r_half^T p_a = r_half (p_b - T); t = r_half T.
//   w_R turns t onto the x axis (w_R t = (s |t|, 0, 0), s = sign(t_x)): the rotation about
//   t x (s, 0, 0) by acos(|t_x| / |t|).
//   R1 = w_R r_half^T (rect_from_cam_a), R2 = w_R r_half (rect_from_cam_b): a point's rectified
//   coordinates differ by w_R t, along x only, so a point projects to the same rectified row in
//   both images.
// The common pinhole P = [f 0 cx; 0 f cy; 0 0 1] of both rectified images (no skew, square
// pixels, the same cx: OpenCV's CALIB_ZERO_DISPARITY), of the first camera's image size:
//   cx, cy = the image centre ((w - 1) / 2, (h - 1) / 2);
//   f = the smallest focal length (the widest view) for which every pixel of the rectified
//       image's border, in both cameras, comes from inside its source image through its lens
//       (ProjectPoint, the lens one-to-one there: DistortionIsMonotoneAlong): the rectified
//       images hold only valid pixels (OpenCV's alpha = 0). Found by bisection on log f between
//       f_min_scale and f_max_scale times the cameras' mean fkv_px (RectifyOptions).
//   P1 = [P | 0], P2 = [P | (f s |t|, 0, 0)^T] (OpenCV's P2(0, 3) = f T_x'), Q as OpenCV's:
//   [1 0 0 -cx; 0 1 0 -cy; 0 0 0 f; 0 0 -1/Tx' 0], Tx' = s |t|.
// For radtan, R1 and R2 are cv::stereoRectify's (same Bouguet split); its P differs (OpenCV's
// focal length and principal points follow other rules), the rectified rows agree.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "camera/rig.h"
#include "sim/render.h"

namespace calibench {

struct RectifyOptions {
  int camera_a = 0;           // The first (left) camera of the pair, an index into the rig.
  int camera_b = 1;           // The second (right) camera.
  double f_min_scale = 0.05;  // f is searched in [f_min_scale, f_max_scale] x the cameras' mean
  double f_max_scale = 20.0;  // focal length (fkv_px).
  bool Check(std::string* why) const;
};

struct Rectification {
  int camera_a = 0, camera_b = 1;
  Eigen::Matrix3d rect_from_cam_a = Eigen::Matrix3d::Identity();  // R1.
  Eigen::Matrix3d rect_from_cam_b = Eigen::Matrix3d::Identity();  // R2.
  double f_px = 0, cx_px = 0, cy_px = 0;                          // The common pinhole P.
  int width = 0, height = 0;                                      // The rectified images' size.
  double baseline_x = 0;  // s |t|: camera a's centre seen along rectified x from b.
  Eigen::Matrix<double, 3, 4> P1() const;
  Eigen::Matrix<double, 3, 4> P2() const;
  Eigen::Matrix4d Q() const;
};

struct RectifySummary {
  bool ok = false;
  std::string error;  // Why not ok (names the camera and the reason).
  Rectification rectification;
};

// The rectification of rig cameras options.camera_a and camera_b. Needs the first camera's image
// size (else an error) and a rig that passes CameraRig::Check.
RectifySummary RectifyPair(const CameraRig& rig, const RectifyOptions& options = {});

// A remap table (cv::remap's map1, map2 as CV_32FC1: cv::Mat(height, width, CV_32FC1, x.data())):
// the source pixel of each rectified pixel, row-major.
struct RectifyMap {
  int width = 0, height = 0;
  std::vector<float> x, y;  // -1 where the rectified pixel has no source.
};

// The remap table of camera `which` (0: camera_a, 1: camera_b): each rectified pixel's ray
// P^-1 (u, v, 1) turned into the camera (R^T) and projected through its lens (ProjectPoint, where
// the lens is one-to-one).
RectifyMap RectifyMaps(const CameraRig& rig, const Rectification& rectification, int which);

// Both images rectified (bilinear, black outside) side by side in one 8-bit image (width 2 w,
// height h), with a dashed horizontal line (alternating black and white, 8 px dashes) every
// `line_spacing_px` rows (0: none): the corners of a well calibrated pair lie on the same row.
// Writing it (cv::imwrite) is the caller's.
GrayImage RectifiedPairImage(const CameraRig& rig, const Rectification& rectification,
                             const GrayImage& image_a, const GrayImage& image_b,
                             int line_spacing_px = 32);

struct VerticalDisparity {
  int points = 0;     // Board points both cameras saw in a frame (matched by equal coordinates).
  double rms_px = 0;  // RMS of v_a - v_b, the rows of a point in the two rectified images.
  double max_px = 0;  // The largest |v_a - v_b|.
};

// The vertical disparity after rectification of the corners both cameras saw: each pixel is
// unprojected through its lens (UnprojectToRay), rotated into the rectified frame and projected
// through P. Points behind the rectified plane are skipped.
VerticalDisparity MeasureVerticalDisparity(const CameraRig& rig, const Rectification& rectification,
                                           const std::vector<RigFrame>& frames);

}  // namespace calibench
