// calibrate --images on a folder with a Kalibr target given as YAML text: shared by
// the tests of tests/calib (bundled, rendered and shared folders).
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "calib/calibrate.h"
#include "calib/image_points.h"
#include "io/target_io.h"

namespace calibench {

// Writes `yaml` to the test's temporary directory as `name`; returns its path.
inline std::string WriteTarget(const std::string& name, const std::string& yaml) {
  std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << yaml;
  return path;
}

// A Kalibr checkerboard target file's text: `cols` x `rows` inner corners, square side `square_m`.
inline std::string CheckerboardTargetYaml(int cols, int rows, double square_m) {
  std::ostringstream yaml;
  yaml << "target_type: 'checkerboard'\ntargetCols: " << cols << "\ntargetRows: " << rows
       << "\nrowSpacingMeters: " << square_m << "\ncolSpacingMeters: " << square_m << "\n";
  return yaml.str();
}

// Detects `target_yaml`'s target in every image of `dir` and calibrates `model` (zhang, then
// ceres).
inline CalibrateReport CalibrateFolder(const std::string& dir, const std::string& target_yaml,
                                       LensModel model, ImageFolderReport* images) {
  CalibrationTarget target;
  std::string why;
  EXPECT_TRUE(LoadTargetYaml(WriteTarget("target.yaml", target_yaml), &target, &why)) << why;
  PointData data;
  std::vector<int> used;
  EXPECT_TRUE(LoadImagePoints(dir, target, &data, images, &used, &why)) << why;
  CalibrateOptions options;
  options.model = model;
  return CalibrateFromPoints(data, options);
}

// What calibrate --images does on a folder: detection, the calibration, then the corners re-fitted
// through each estimate of the lens and the camera recalibrated (IterateCornersThroughTheLens), at
// most `passes` times (calibrate's default: --corner-iterations).
struct FolderCalibration {
  CalibrateReport first;  // Before any re-fit.
  ImageCalibration last;  // After the last re-fit (its report is the result).
  std::string log;        // The passes' lines.
};
inline FolderCalibration CalibrateFolderThroughTheLens(
    const std::string& dir, const CalibrationTarget& target, LensModel model,
    int passes = CalibrateOptions().corner_iterations) {
  FolderCalibration out;
  ImageCalibration& state = out.last;
  ImagePointOptions image_options;
  image_options.lens = FamilyOf(model);
  image_options.detection_cache = &state.detections;
  std::string why;
  EXPECT_TRUE(LoadImagePoints(dir, target, &state.data, &state.images, &state.used_index, &why,
                              image_options))
      << why;
  CalibrateOptions options;
  options.model = model;
  state.report = CalibrateFromPoints(state.data, options);
  EXPECT_TRUE(state.report.IsUsable()) << state.report.ceres.message;
  out.first = state.report;
  std::ostringstream log;
  IterateCornersThroughTheLens(dir, target, image_options, options, passes, &state, log);
  out.log = log.str();
  return out;
}
// The same with the target given as YAML text.
inline FolderCalibration CalibrateFolderThroughTheLens(const std::string& dir,
                                                       const std::string& target_yaml,
                                                       LensModel model) {
  CalibrationTarget target;
  std::string why;
  EXPECT_TRUE(LoadTargetYaml(WriteTarget("target.yaml", target_yaml), &target, &why)) << why;
  return CalibrateFolderThroughTheLens(dir, target, model);
}

// Ceres refines zhang's optimum; both minimise the same reprojection error on the same corners,
// so they must agree far below the statistical uncertainty (0.4 px here).
constexpr double kSameOptimumPx = 1e-3;

}  // namespace calibench
