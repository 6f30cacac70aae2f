// What `calibench calibrate` prints: a calibration's result as text, apart from the work
// (calibrate_camera.h). Every number is printed to a fixed precision, so the text of the same
// calibration is the same byte for byte.
#pragma once

#include <string>
#include <vector>

#include "calib/calibrate_camera.h"

namespace calibench {

// The whole report: the model selection's table (select_model), the calibration
// (FormatCalibrateReport below) and, from images, the images' table (FormatImageReport). A
// result refused before any fit (kBadImages, kBadInit, options that fail Check) is one line,
// "calibration refused: " and its message.
std::string FormatCalibrateReport(const CalibrateResult& result);

// The calibration: intrinsics +- std for ceres (and the jackknife std when computed) beside the
// initialisation's, RMS, per-view RMS.
std::string FormatCalibrateReport(const CalibrateReport& report, const PointData& data);

// Per image: used or why not, points, per-view RMS and an outlier flag (view RMS above
// kOutlierFactor times the median view RMS); the detection rate; a warning above
// kHighReprojectionPx. `used_index` maps data views to report images.
constexpr double kOutlierFactor = 3.0;
std::string FormatImageReport(const ImageFolderReport& images, const std::vector<int>& used_index,
                              const CalibrateReport& report);

}  // namespace calibench
