// Zhang's method through OpenCV (`cv::calibrateCamera`) for planar targets: the `zhang` method and
// the initialisation of `ceres` on planar data. Every view's points must lie on z = 0 of the board
// frame. OpenCV fixes the skew: the result always has phi = 90 degrees (said in the message).
#pragma once

#include <string>
#include <vector>

#include "batch/refine.h"
#include "batch/wide_init.h"
#include "camera/camera.h"
#include "camera/pose.h"
#include "camera/view.h"
#include "util/status.h"

namespace calibench {

struct ZhangOptions {
  LensModel model = LensModel::kPinholeK2;
  int image_width = 640;  // Used by OpenCV to initialise the principal point.
  int image_height = 480;
  int view_stride = 1;  // Use every view_stride-th view (calibrateCamera slows as N^2.5).
  bool Check(std::string* why) const;
};

struct ZhangResult : MethodSummary {
  CameraIntrinsics intrinsics;
  std::vector<Rigid3> cam_from_board;  // One per used view.
  std::vector<int> used_views;         // Indices into the input.
  IntrinsicsArray intrinsics_std{};    // OpenCV's stdDeviationsIntrinsics; NaN where fixed.
  double rms_reproj_px = 0.0;          // Per-point RMS (OpenCV's figure).
};

ZhangResult CalibrateZhang(const std::vector<View>& planar_views, const ZhangOptions& options);

// The wide start (batch/wide_init.h: the omnidirectional families, which OpenCV has not) as a
// ZhangResult: its status, intrinsics, poses, used views and RMS; no standard deviations (NaN).
ZhangResult FromWideStart(const WideInitResult& wide);

}  // namespace calibench
