// Calibrating a camera from C++ with calib/ alone: Zhang's published points (data/zhang, read by
// io/points_io.h), pinhole-k2 with skew, the report `calibench calibrate --points data/zhang
// --model pinhole-k2 --skew` prints (examples/CMakeLists.txt checks that it is the same text).
//
//   calibench_example_calibrate_folder [POINTS_DIR_OR_FILE]   (default: the bundled data/zhang)
#include <iostream>
#include <string>

#include "calib/calibrate_camera.h"
#include "calib/calibrate_report.h"
#include "io/points_io.h"

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : CALIBENCH_SOURCE_DIR "/data/zhang";
  calibench::PointData data;
  std::string why;
  if (!calibench::LoadPointData(path, &data, &why)) {
    std::cerr << "calibrate_folder: " << why << "\n";
    return 2;
  }
  calibench::CalibrateOptions options;
  options.model = calibench::LensModel::kPinholeK2;
  options.estimate_skew = true;
  const calibench::CalibrateResult result = calibench::CalibratePoints(data, options);
  std::cout << calibench::FormatCalibrateReport(result);
  if (!result.IsUsable()) return 4;
  const calibench::CameraFile& camera = result.calibration.camera;
  std::cerr << "calibrate_folder: " << camera.ModelName() << ", f.ku " << camera.intrinsics.fku_px
            << " px\n";
  return 0;
}
