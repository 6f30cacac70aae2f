#include "bench/app/calibrate_cmd.h"

#include <iostream>
#include <optional>

#include "calib/calibrate_report.h"
#include "calib/calibration_page.h"
#include "calib/cross_validate.h"
#include "io/camera_io.h"
#include "io/points_io.h"
#include "io/target_io.h"

namespace calibench {

std::string LensModelList() {
  std::string list;
  for (const std::string& name : LensModelNames()) {
    list += (list.empty() ? "" : ", ") + name;
  }
  return list;
}

namespace {

// Writes camera.yaml of a usable calibration and, with `page`, its page (calib/calibration_page.h)
// beside it (exit 0), or exits 4 (unusable) or 3 (the camera file unwritable).
int FinishCalibration(const CalibrateResult& result, const CrossValidation* cross_validation,
                      const std::string& out_path, CameraFormat format, bool page) {
  std::string why;
  const CalibrateReport& report = result.calibration;
  if (!report.IsUsable()) return 4;
  if (!WriteCameraFile(out_path, format, report.camera, &why)) {
    std::cerr << "calibench: --out: " << why << "\n";
    return 3;
  }
  std::cerr << "calibench: wrote " << out_path << " (" << ToString(format) << ")\n";
  if (!page) return 0;
  // The camera file is what was asked for: a page that cannot be written is a warning.
  CalibrationPageFiles files;
  if (!WriteCalibrationPage(out_path, result, cross_validation, &files, &why)) {
    std::cerr << "calibench: warning: the calibration page was not written: " << why << "\n";
    return 0;
  }
  std::cerr << "calibench: wrote " << files.markdown << " and " << files.figures.size()
            << " figures\n";
  return 0;
}

// calibrate --images: the target read (io/target_io.h), the flags of the corner search, then
// CalibrateImages (its corner passes' lines on stderr as they run).
int CalibrateImageFolder(const CalibrateArgs& args, const CalibrateOptions& options,
                         CalibrateResult* result) {
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
  ImagePointOptions image_options;
  image_options.predict_missing_tags = !args.no_tag_prediction;
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
  *result = CalibrateImages(args.images[0], target, image_options, options, &std::cerr);
  const char* bad_input = result->status == CalibrateResult::Status::kBadImages ? "--images"
                          : result->status == CalibrateResult::Status::kBadInit ? "--init"
                                                                                : nullptr;
  if (bad_input) {
    std::cerr << "calibench: " << bad_input << ": " << result->message << "\n";
    return 2;
  }
  return 0;
}

}  // namespace

int Calibrate(const CalibrateArgs& args) {
  if (args.images.size() >= 2) return CalibrateRig(args);
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
  options.select_model = auto_model;
  options.estimate_skew = args.skew;
  options.corner_iterations = args.corner_iterations;
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
  CalibrateResult result;
  if (!args.images.empty()) {
    const int status = CalibrateImageFolder(args, options, &result);
    if (status != 0) return status;
  } else {
    PointData data;
    if (!LoadPointData(args.points_path, &data, &why)) {
      std::cerr << "calibench: --points: " << why << "\n";
      return 2;
    }
    result = CalibratePoints(data, options);
  }
  std::cout << FormatCalibrateReport(result);
  std::optional<CrossValidation> cross_validation;
  if (args.cross_validate && result.IsUsable()) {
    if (args.evaluate) {
      std::cerr << "calibench: --cross-validate: nothing to cross-validate with --evaluate (the "
                   "given camera is kept fixed)\n";
    } else {
      cross_validation = CrossValidate(result, options);
      std::cout << FormatCrossValidation(*cross_validation);
    }
  }
  return FinishCalibration(result, cross_validation ? &*cross_validation : nullptr, args.out_path,
                           format, !args.no_page);
}

}  // namespace calibench
