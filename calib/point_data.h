// Calibration points: the views of a planar target (its points in the board frame and their
// pixels), as read from point files (io/points_io.h) or found in images (calib/image_points.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/view.h"

namespace calibench {

struct PointData {
  std::string format;  // "zhang", "opencv-calib", "images+aprilgrid" or "images+checkerboard"
  std::vector<View> views;
  // What each view is called in messages: its file ("data3.txt", "view07.png"); empty (an OpenCV
  // .dat file, one file for every view): "view <index>".
  std::vector<std::string> view_names;
  int image_width = 640;
  int image_height = 480;
  std::optional<CameraIntrinsics> reference;  // Carried by the file (OpenCV format).
};

}  // namespace calibench
