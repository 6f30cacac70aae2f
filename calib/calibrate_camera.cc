#include "calib/calibrate_camera.h"

#include <sstream>
#include <utility>

namespace calibench {

namespace {

// CalibrateFromPoints; with select_model, the model selection and its pick, which *options then
// holds. False when the selection picks nothing.
bool FitCamera(const PointData& data, CalibrateOptions* options, CalibrateResult* result) {
  if (!options->select_model) {
    result->calibration = CalibrateFromPoints(data, *options);
    return true;
  }
  ModelSelectOptions select;
  select.estimate_skew = options->estimate_skew;
  result->selection = SelectLensModel(data, select);
  if (!result->selection->IsUsable()) return false;
  const ModelScore& chosen = result->selection->scores[result->selection->chosen];
  options->model = chosen.model;
  result->calibration = chosen.report;
  return true;
}

// The status of a fitted result, the jackknife and the projection uncertainty added.
void Finish(const CalibrateOptions& options, CalibrateResult* result) {
  result->model = options.model;
  AddJackknife(result->data, options, &result->calibration);
  AddProjectionUncertainty(result->data, options, &result->calibration);
  result->status = result->calibration.IsUsable() ? CalibrateResult::Status::kOk
                                                  : CalibrateResult::Status::kFailed;
}

}  // namespace

CalibrateResult CalibratePoints(const PointData& data, const CalibrateOptions& options) {
  CalibrateResult result;
  result.data = data;
  CalibrateOptions fitted = options;
  if (!options.Check(&result.message)) return result;
  if (!FitCamera(result.data, &fitted, &result)) return result;
  Finish(fitted, &result);
  return result;
}

CalibrateResult CalibrateImages(const std::string& dir, const CalibrationTarget& target,
                                ImagePointOptions images, const CalibrateOptions& options,
                                std::ostream* log) {
  CalibrateResult result;
  if (!options.Check(&result.message)) return result;
  // With init, the given camera's lens draws the corner fit from the first pass. select_model:
  // the candidates include wide lenses, whose bent tag edges need the curved fit; a checkerboard
  // is found as OpenCV's procedure finds it (the classic search first), since a pinhole pick
  // keeps those corners.
  const bool aprilgrid = target.type == CalibrationTarget::Type::kAprilGrid;
  images.lens = !options.select_model ? FamilyOf(options.model)
                : aprilgrid           ? LensFamily::kUnified
                                      : LensFamily::kRadTan;
  if (options.init) images.camera = options.init->intrinsics;
  const bool photometric =
      images.refinement.value_or(CornerRefinement::kPhotometric) == CornerRefinement::kPhotometric;
  ImageCalibration state;
  images.detection_cache = &state.detections;
  if (!LoadImagePoints(dir, target, &state.data, &state.images, &state.used_index, &result.message,
                       images)) {
    result.status = CalibrateResult::Status::kBadImages;
    return result;
  }
  if (options.init &&
      !CheckInitImageSize(*options.init, options.init_path, state.data, dir, &result.message)) {
    result.status = CalibrateResult::Status::kBadInit;
    return result;
  }
  CalibrateOptions fitted = options;
  if (!FitCamera(state.data, &fitted, &result)) return result;
  state.report = result.calibration;
  // The tags' re-fit through the lens is the photometric fit's; a checkerboard's is its own.
  const bool refits = !aprilgrid || photometric;
  if (!options.evaluate_only && fitted.model != LensModel::kPinhole &&
      options.corner_iterations > 0 && refits) {
    std::ostringstream quiet;
    IterateCornersThroughTheLens(dir, target, images, fitted, options.corner_iterations, &state,
                                 log ? *log : quiet);
  }
  result.data = std::move(state.data);
  result.images = std::move(state.images);
  result.used_index = std::move(state.used_index);
  result.calibration = std::move(state.report);
  Finish(fitted, &result);
  return result;
}

}  // namespace calibench
