// calibrate's built-in cross-validation (calib/cross_validate.h).
#include "calib/cross_validate.h"

namespace calibench {

CrossValidation CrossValidate(const CalibrateResult& result, const CalibrateOptions& options) {
  CrossValidation cv;
  const std::vector<int>& used = result.calibration.zhang.used_views;
  if (!result.IsUsable()) {
    cv.message = "no usable calibration to cross-validate";
    return cv;
  }
  if (static_cast<int>(used.size()) < 2 * kMinViewsPerHalf) {
    cv.message = std::to_string(used.size()) + " views: cross-validation needs at least " +
                 std::to_string(2 * kMinViewsPerHalf) + " (" + std::to_string(kMinViewsPerHalf) +
                 " per half)";
    return cv;
  }
  CalibrateOptions half_options = options;
  half_options.model = result.model;
  half_options.select_model = false;
  half_options.init.reset();
  half_options.evaluate_only = false;
  for (int h = 0; h < 2; ++h) {
    PointData half = result.data;
    half.views.clear();
    half.view_names.clear();
    for (size_t k = static_cast<size_t>(h); k < used.size(); k += 2) {
      half.views.push_back(result.data.views[used[k]]);
      if (static_cast<size_t>(used[k]) < result.data.view_names.size()) {
        half.view_names.push_back(result.data.view_names[used[k]]);
      }
    }
    if (half.view_names.size() != half.views.size()) half.view_names.clear();
    const CalibrateResult fit = CalibratePoints(half, half_options);
    if (!fit.IsUsable()) {
      cv.message = std::string("the ") + (h == 0 ? "first" : "second") +
                   " half does not calibrate: " + fit.calibration.ceres.message + fit.message;
      return cv;
    }
    cv.halves[h] = fit.calibration.camera;
    cv.half_views[h] = static_cast<int>(half.views.size());
  }
  cv.comparison = CompareCameras(cv.halves[0], cv.halves[1], CompareOptions());
  cv.ok = cv.comparison.ok;
  if (!cv.ok) cv.message = cv.comparison.message;
  return cv;
}

std::string FormatCrossValidation(const CrossValidation& cv) {
  if (!cv.ok) return "cross-validation: not done: " + cv.message + "\n";
  return "Cross-validation (two halves of the views, " + std::to_string(cv.half_views[0]) +
         " and " + std::to_string(cv.half_views[1]) + ", calibrated apart):\n" +
         FormatComparison(cv.comparison, "half 1", "half 2");
}

}  // namespace calibench
