// calibrate --images on a folder with a Kalibr target given as YAML text: shared by
// calibrate_images_test.cc (bundled and rendered folders) and shared_data_test.cc.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "bench/app/calibrate.h"
#include "bench/app/image_points.h"
#include "bench/config/target_io.h"

namespace calibench {

// Writes `yaml` to the test's temporary directory as `name`; returns its path.
inline std::string WriteTarget(const std::string& name, const std::string& yaml) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << yaml;
  return path;
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

// Ceres refines zhang's optimum; both minimise the same reprojection error on the same corners,
// so they must agree far below the statistical uncertainty (0.4 px here).
constexpr double kSameOptimumPx = 1e-3;

}  // namespace calibench
