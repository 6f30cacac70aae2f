// Calibrating a camera, the whole of `calibench calibrate` but its flags and files: from points
// (CalibratePoints) or from a folder of images of a target (CalibrateImages), the lens model given
// or chosen (model_select.h), the corners re-fitted through the lens (images), the jackknife std.
// The result is a value; calib/calibrate_report.h prints it; io/ reads the inputs and writes the
// camera file.
//
//   PointData data;  // io/points_io.h LoadPointData, or your own views
//   CalibrateOptions options;
//   options.model = LensModel::kPinholeK2;
//   const CalibrateResult result = CalibratePoints(data, options);
//   std::cout << FormatCalibrateReport(result);
//   if (result.IsUsable()) UseCamera(result.calibration.camera);
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "calib/calibrate.h"
#include "calib/image_points.h"
#include "calib/model_select.h"

namespace calibench {

// One camera's calibration and what it came from. (A rig will hold one CalibrateReport per
// camera.)
struct CalibrateResult {
  // kBadImages: no image of the folder shows the target; kBadInit: the given camera is for
  // another image size (message says why for both); kFailed: no usable calibration (the model
  // selection or the calibration says why).
  enum class Status { kOk, kBadImages, kBadInit, kFailed };
  Status status = Status::kFailed;
  std::string message;
  PointData data;                           // The views calibrated.
  std::optional<ModelSelection> selection;  // options.select_model: every candidate's fit.
  LensModel model = LensModel::kPinholeK2;  // The model fitted (the selection's pick).
  CalibrateReport calibration;
  // CalibrateImages: what each image gave; data.views[i] comes from images->images[used_index[i]].
  std::optional<ImageFolderReport> images;
  std::vector<int> used_index;
  bool IsUsable() const { return status == Status::kOk; }
};

// The camera of `data`'s views: options.model fitted (or, with options.select_model, the model
// SelectLensModel picks), then the jackknife std as options.jackknife asks.
CalibrateResult CalibratePoints(const PointData& data, const CalibrateOptions& options);

// The camera of the images of `dir` showing `target`: the corners found (LoadImagePoints; `images`
// says how: threads, refinement, tag prediction; its lens, camera and cache are set here), the
// camera fitted as CalibratePoints fits it, the corners re-fitted through the lens at most
// options.corner_iterations times (a lens that distorts; IterateCornersThroughTheLens, its lines
// to *log when not null), then the jackknife std.
CalibrateResult CalibrateImages(const std::string& dir, const CalibrationTarget& target,
                                ImagePointOptions images, const CalibrateOptions& options,
                                std::ostream* log = nullptr);

}  // namespace calibench
