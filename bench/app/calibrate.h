// Calibrating a camera from point files: zhang (cv::calibrateCamera) initialises, ceres refines
// (per-view board poses, the chosen lens model, optional skew) and reports standard deviations
// from its covariance (sigma estimated from the residuals).
#pragma once

#include <string>

#include "batch/refine.h"
#include "batch/zhang.h"
#include "bench/app/image_points.h"
#include "bench/app/points_io.h"

namespace calibench {

struct CalibrateOptions {
  LensModel model = LensModel::kPinholeK2;
  bool estimate_skew = false;
};

struct CalibrateReport {
  ZhangResult zhang;
  RefineResult ceres;
  CameraFile camera;  // What camera.yaml holds (the ceres result).
  bool IsUsable() const { return ceres.IsUsable(); }
};

CalibrateReport CalibrateFromPoints(const PointData& data, const CalibrateOptions& options);

// Human-readable report: intrinsics +- std for ceres beside zhang, RMS, per-view RMS.
std::string FormatCalibrateReport(const CalibrateReport& report, const PointData& data);

// Per image: used or why not, points, per-view RMS and an outlier flag (view RMS above
// kOutlierFactor times the median view RMS). `used_index` maps data views to report images.
constexpr double kOutlierFactor = 3.0;
// A calibration whose reprojection RMS exceeds this is flagged: detected corners are good to
// ~0.1 px and real lenses fit to < 0.5 px with a matching model, so > 1 px means the target
// geometry (spacing, size) or the lens model does not match the images.
constexpr double kHighReprojectionPx = 1.0;
std::string FormatImageReport(const ImageFolderReport& images, const std::vector<int>& used_index,
                              const CalibrateReport& report);

}  // namespace calibench
