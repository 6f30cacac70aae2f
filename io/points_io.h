// Readers for published calibration point files.
//
//  - Zhang's format (MSR-TR-98-71): a folder with Model.txt (the board's corners, x y per corner,
//    4 corners a line, z = 0) and data1.txt, data2.txt, ... (the detected pixels, same order).
//  - OpenCV's regression format (opencv_extra cameracalibration/calib1.dat): image size, pattern
//    size, view count, flags, object points per view, image points per view, then the reference
//    fx fy / cx cy / k1 k2 p1 p2 that the file carries (kept as `reference`).
//
// The views are calib/point_data.h's; the camera files calibrate writes are io/camera_io.h's.
#pragma once

#include <string>

#include "calib/point_data.h"

namespace calibench {

// `path`: a Zhang folder or an OpenCV .dat file. On failure, *why names the file and the reason.
bool LoadPointData(const std::string& path, PointData* data, std::string* why);

}  // namespace calibench
