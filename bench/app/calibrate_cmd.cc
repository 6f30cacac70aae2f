#include "bench/app/calibrate_cmd.h"

#include <iostream>

#include "calib/calibrate.h"
#include "calib/model_select.h"

namespace calibench {

std::string LensModelList() {
  std::string list;
  for (const std::string& name : LensModelNames()) {
    list += (list.empty() ? "" : ", ") + name;
  }
  return list;
}

namespace {

// Writes camera.yaml of a usable calibration (exit 0), or exits 4 (unusable) or 3 (unwritable).
int FinishCalibration(const CalibrateReport& report, const std::string& out_path,
                      CameraFormat format) {
  std::string why;
  if (!report.IsUsable()) return 4;
  if (!WriteCameraFile(out_path, format, report.camera, &why)) {
    std::cerr << "calibench: --out: " << why << "\n";
    return 3;
  }
  std::cerr << "calibench: wrote " << out_path << " (" << ToString(format) << ")\n";
  return 0;
}

// CalibrateFromPoints; with --model auto, the model selection (its table printed) and its pick,
// which *options then holds. False when auto picks nothing.
bool FitCamera(const PointData& data, bool auto_model, CalibrateOptions* options,
               CalibrateReport* report) {
  if (!auto_model) {
    *report = CalibrateFromPoints(data, *options);
    return true;
  }
  ModelSelectOptions select;
  select.estimate_skew = options->estimate_skew;
  const ModelSelection selection = SelectLensModel(data, select);
  std::cout << FormatModelSelection(selection) << "\n";
  if (!selection.IsUsable()) return false;
  const ModelScore& chosen = selection.scores[selection.chosen];
  options->model = chosen.model;
  *report = chosen.report;
  return true;
}

// calibrate --images: the target's corners in the images, the fit (FitCamera), the corners re-fit
// through the lens (a lens that distorts; tags: with the photometric fit), the reports and the
// camera file.
int CalibrateImages(const CalibrateArgs& args, bool auto_model, CalibrateOptions options,
                    CameraFormat format) {
  CalibrationTarget target;
  std::string why;
  if (args.target_path.empty()) {
    std::cerr << "calibench: --images needs --target TARGET.yaml (Kalibr aprilgrid or "
                 "checkerboard)\n";
    return 2;
  }
  if (!LoadTargetYaml(args.target_path, &target, &why)) {
    std::cerr << "calibench: --target: " << why << "\n";
    return 2;
  }
  // With --init, the given camera's lens draws the corner fit from the first pass.
  ImagePointOptions image_options;
  image_options.predict_missing_tags = !args.no_tag_prediction;
  // --model auto: the candidates include wide lenses, whose bent tag edges need the curved fit; a
  // checkerboard is found as OpenCV's procedure finds it (the classic search first), since a
  // pinhole pick keeps those corners.
  const bool aprilgrid = target.type == CalibrationTarget::Type::kAprilGrid;
  image_options.lens = !auto_model ? FamilyOf(options.model)
                       : aprilgrid ? LensFamily::kUnified
                                   : LensFamily::kRadTan;
  if (options.init) image_options.camera = options.init->intrinsics;
  image_options.threads = args.threads;
  if (!args.corner_refinement.empty()) {
    CornerRefinement refinement;
    if (!ParseCornerRefinement(args.corner_refinement, &refinement)) {
      std::cerr << "calibench: --corner-refinement: '" << args.corner_refinement
                << "' is not a refinement\n";
      return 2;
    }
    image_options.refinement = refinement;
  }
  const bool photometric = image_options.refinement.value_or(CornerRefinement::kPhotometric) ==
                           CornerRefinement::kPhotometric;
  ImageCalibration state;
  image_options.detection_cache = &state.detections;
  if (!LoadImagePoints(args.images_dir, target, &state.data, &state.images, &state.used_index, &why,
                       image_options)) {
    std::cerr << "calibench: --images: " << why << "\n";
    return 2;
  }
  if (options.init &&
      !CheckInitImageSize(*options.init, args.init_path, state.data, args.images_dir, &why)) {
    std::cerr << "calibench: --init: " << why << "\n";
    return 2;
  }
  if (!FitCamera(state.data, auto_model, &options, &state.report)) return 4;
  // The tags' re-fit through the lens is the photometric fit's; a checkerboard's is its own.
  const bool refits = !aprilgrid || photometric;
  if (!args.evaluate && options.model != LensModel::kPinhole && args.corner_iterations > 0 &&
      refits) {
    IterateCornersThroughTheLens(args.images_dir, target, image_options, options,
                                 args.corner_iterations, &state, std::cerr);
  }
  AddJackknife(state.data, options, &state.report);
  const CalibrateReport& report = state.report;
  std::cout << FormatCalibrateReport(report, state.data);
  std::cout << FormatImageReport(state.images, state.used_index, report);
  return FinishCalibration(report, args.out_path, format);
}

}  // namespace

int Calibrate(const CalibrateArgs& args) {
  CalibrateOptions options;
  std::string why;
  const bool auto_model = args.model == "auto";
  if (!auto_model && !ParseLensModel(args.model, &options.model)) {
    std::cerr << "calibench: --model: unknown lens model '" << args.model << "' ("
              << LensModelList() << ", auto)\n";
    return 2;
  }
  if (auto_model && !args.init_path.empty()) {
    std::cerr << "calibench: --model auto fits every candidate model from scratch; --init gives "
                 "one camera (name its --model, or drop --init)\n";
    return 2;
  }
  options.estimate_skew = args.skew;
  if (args.jackknife == "on") options.jackknife = CalibrateOptions::Jackknife::kOn;
  if (args.jackknife == "off") options.jackknife = CalibrateOptions::Jackknife::kOff;
  CameraFormat format = CameraFormatFromPath(args.out_path);
  if (!args.format.empty() && !ParseCameraFormat(args.format, &format, &why)) {
    std::cerr << "calibench: --format: " << why << "\n";
    return 2;
  }
  if (!args.init_path.empty()) {
    CameraFile init;
    if (!ReadCameraFile(args.init_path, &init, &why)) {
      std::cerr << "calibench: --init: " << why << "\n";
      return 2;
    }
    // The given camera's own model, unless --model says otherwise (refining into another one).
    if (!args.model_given || args.evaluate) options.model = init.lens_model;
    if (!args.skew || args.evaluate) options.estimate_skew = init.estimate_skew;
    options.init = init;
    options.init_path = args.init_path;
    options.evaluate_only = args.evaluate;
  } else if (args.evaluate) {
    std::cerr << "calibench: --evaluate needs --init CAMERA_FILE (the calibration to evaluate)\n";
    return 2;
  }
  if (!args.images_dir.empty()) return CalibrateImages(args, auto_model, options, format);
  PointData data;
  if (!LoadPointData(args.points_path, &data, &why)) {
    std::cerr << "calibench: --points: " << why << "\n";
    return 2;
  }
  CalibrateReport report;
  if (!FitCamera(data, auto_model, &options, &report)) return 4;
  AddJackknife(data, options, &report);
  std::cout << FormatCalibrateReport(report, data);
  return FinishCalibration(report, args.out_path, format);
}

}  // namespace calibench
