// Readers for published calibration point files, and the camera.yaml writer.
//
//  - Zhang's format (MSR-TR-98-71): a folder with Model.txt (the board's corners, x y per corner,
//    4 corners a line, z = 0) and data1.txt, data2.txt, ... (the detected pixels, same order).
//  - OpenCV's regression format (opencv_extra cameracalibration/calib1.dat): image size, pattern
//    size, view count, flags, object points per view, image points per view, then the reference
//    fx fy / cx cy / k1 k2 p1 p2 that the file carries (kept as `reference`).
//
// The camera files calibrate writes are bench/config/camera_io.h's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/view.h"

namespace calibench {

struct PointData {
  std::string format;  // "zhang" or "opencv-calib"
  std::vector<View> views;
  // What each view is called in messages: its file ("data3.txt", "view07.png"); empty (an OpenCV
  // .dat file, one file for every view): "view <index>".
  std::vector<std::string> view_names;
  int image_width = 640;
  int image_height = 480;
  std::optional<CameraIntrinsics> reference;  // Carried by the file (OpenCV format).
};

// `path`: a Zhang folder or an OpenCV .dat file. On failure, *why names the file and the reason.
bool LoadPointData(const std::string& path, PointData* data, std::string* why);

}  // namespace calibench
