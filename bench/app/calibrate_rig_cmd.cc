// `calibench calibrate --images SRC --images SRC ...`: a rig (calib/calibrate_rig.h). The sources
// paired into frames (calib/rig_images.h), the rig calibrated, its report on stdout, its files
// written (io/rig_io.h) and the first pair rectified into one PNG (calib/rectify.h).
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "bench/app/calibrate_cmd.h"
#include "calib/calibrate_rig.h"
#include "calib/calibration_page.h"
#include "calib/image_points.h"
#include "calib/rectify.h"
#include "calib/rig_images.h"
#include "io/rig_io.h"
#include "io/target_io.h"

namespace calibench {

namespace {

namespace fs = std::filesystem;

// --model: one name, or a comma-separated list.
bool ParseModels(const std::string& text, std::vector<LensModel>* models, std::string* why) {
  models->clear();
  std::stringstream stream(text);
  std::string name;
  while (std::getline(stream, name, ',')) {
    LensModel model;
    if (!ParseLensModel(name, &model)) {
      *why = "unknown lens model '" + name + "' (" + LensModelList() + ")";
      return false;
    }
    models->push_back(model);
  }
  if (models->empty()) *why = "no lens model";
  return !models->empty();
}

// The first frame both of the first two cameras saw: its two images rectified side by side.
int WriteRectifiedPair(const CalibrateRigResult& result, const std::vector<RigCameraImages>& cams,
                       const std::string& path) {
  RectifyOptions options;
  const RectifySummary rectify = RectifyPair(result.rig.rig, options);
  if (!rectify.ok) {
    std::cerr << "calibench: --rectified: " << rectify.error << "\n";
    return 3;
  }
  for (size_t f = 0; f < result.view_of_frame.size(); ++f) {
    if (cams[0].files_by_frame[f].empty() || cams[1].files_by_frame[f].empty()) continue;
    GrayImage a, b;
    std::string why, note;
    if (!ReadGray8(cams[0].dir + "/" + cams[0].files_by_frame[f], &a, &why, &note) ||
        !ReadGray8(cams[1].dir + "/" + cams[1].files_by_frame[f], &b, &why, &note)) {
      std::cerr << "calibench: --rectified: " << why << "\n";
      return 3;
    }
    GrayImage pair = RectifiedPairImage(result.rig.rig, rectify.rectification, a, b);
    const cv::Mat mat(pair.height, pair.width, CV_8UC1, pair.pixels.data());
    const std::string tmp = path + ".tmp.png";
    if (!cv::imwrite(tmp, mat)) {
      std::cerr << "calibench: --rectified: " << path << ": cannot write the image\n";
      return 3;
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
      std::cerr << "calibench: --rectified: " << path << ": " << ec.message() << "\n";
      fs::remove(tmp, ec);
      return 3;
    }
    std::cerr << "calibench: wrote " << path << " (frame " << result.frame_names[f]
              << " rectified, lines every 32 rows)\n";
    return 0;
  }
  std::cerr << "calibench: --rectified: cameras 0 and 1 share no frame\n";
  return 3;
}

}  // namespace

int CalibrateRig(const CalibrateArgs& args) {
  std::string why;
  CalibrateRigOptions options;
  if (args.model == "auto") {
    options.select_model = true;
    options.models.clear();
  } else if (!ParseModels(args.model, &options.models, &why)) {
    std::cerr << "calibench: --model: " << why << "\n";
    return 2;
  }
  const int num_cameras = static_cast<int>(args.images.size());
  if (options.models.size() > 1 && static_cast<int>(options.models.size()) != num_cameras) {
    std::cerr << "calibench: --model: " << options.models.size() << " models for " << num_cameras
              << " cameras (--images): give one for all or one per camera\n";
    return 2;
  }
  options.estimate_skew = args.skew;
  options.corner_iterations = args.corner_iterations;
  if (args.jackknife == "on") options.jackknife = CalibrateOptions::Jackknife::kOn;
  if (args.jackknife == "off") options.jackknife = CalibrateOptions::Jackknife::kOff;
  if (args.target_path.empty()) {
    std::cerr << "calibench: --images needs --target TARGET.yaml (Kalibr aprilgrid or "
                 "checkerboard)\n";
    return 2;
  }
  CalibrationTarget target;
  if (!LoadTargetYaml(args.target_path, &target, &why)) {
    std::cerr << "calibench: --target: " << why << "\n";
    return 2;
  }
  if (!args.init_path.empty()) {
    RigFile init;
    if (!ReadRigFile(args.init_path, &init, &why)) {
      std::cerr << "calibench: --init: " << why << "\n";
      return 2;
    }
    options.init = init.rig;
    options.init_path = args.init_path;
    options.models.clear();
    for (const RigCamera& camera : init.rig.cameras) options.models.push_back(camera.lens_model);
    options.evaluate_only = args.evaluate;
  } else if (args.evaluate) {
    std::cerr << "calibench: --evaluate needs --init CAMCHAIN (the rig to evaluate)\n";
    return 2;
  }
  // The files: --out's format (or --format), the rig's default name when --out was not given;
  // checked before the calibration, which may take minutes.
  std::string out = args.out_path;
  if (!args.out_given) out = num_cameras == 2 ? "stereo.yaml" : "camchain.yaml";
  CameraFormat format = CameraFormatFromPath(out);
  if (!args.format.empty() && !ParseCameraFormat(args.format, &format, &why)) {
    std::cerr << "calibench: --format: " << why << "\n";
    return 2;
  }
  if (format == CameraFormat::kOpenCv && num_cameras != 2) {
    std::cerr << "calibench: --out: " << out
              << ": an OpenCV stereo file holds 2 cameras, the rig has " << num_cameras
              << ": write a Kalibr camchain (*camchain*.yaml) or mrcal models "
              << "(.cameramodel)\n";
    return 2;
  }
  const fs::path out_dir = fs::path(out).parent_path();
  if (!out_dir.empty() && !fs::is_directory(out_dir)) {
    std::cerr << "calibench: --out: " << out << ": the folder " << out_dir.string()
              << " does not exist\n";
    return 2;
  }
  // The images, paired into frames.
  const RigImageSummary pairing = PairRigImages(args.images);
  if (!pairing.ok) {
    std::cerr << "calibench: --images: " << pairing.error << "\n";
    return 2;
  }
  std::cout << pairing.Report(args.images);
  std::vector<RigCameraImages> cameras(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    cameras[c].source = args.images[c];
    for (const RigImageFrame& frame : pairing.frames) {
      const std::string& path = frame.path_by_camera[c];
      if (!path.empty() && cameras[c].dir.empty()) cameras[c].dir = fs::path(path).parent_path();
    }
  }
  for (const RigImageFrame& frame : pairing.frames) {
    for (int c = 0; c < num_cameras; ++c) {
      const std::string& path = frame.path_by_camera[c];
      if (!path.empty() && fs::path(path).parent_path() != fs::path(cameras[c].dir)) {
        std::cerr << "calibench: --images: " << args.images[c]
                  << ": its images must be in one folder\n";
        return 2;
      }
      cameras[c].files_by_frame.push_back(path.empty() ? "" : fs::path(path).filename().string());
    }
  }
  ImagePointOptions images;
  images.threads = args.threads;
  images.predict_missing_tags = !args.no_tag_prediction;
  if (!args.corner_refinement.empty()) {
    CornerRefinement refinement;
    if (!ParseCornerRefinement(args.corner_refinement, &refinement)) {
      std::cerr << "calibench: --corner-refinement: '" << args.corner_refinement
                << "' is not a refinement\n";
      return 2;
    }
    images.refinement = refinement;
  }
  const CalibrateRigResult result =
      CalibrateRigImages(cameras, target, images, options, &std::cerr);
  std::cout << FormatRigReport(result);
  if (!result.IsUsable()) {
    const bool bad_input = result.status == CalibrateRigResult::Status::kBadImages ||
                           result.status == CalibrateRigResult::Status::kBadInit ||
                           result.status == CalibrateRigResult::Status::kDisconnected;
    std::cerr << "calibench: " << (bad_input ? "--images: " : "") << result.message << "\n";
    return bad_input ? 2 : 4;
  }
  RigFile file;
  file.rig = result.rig.rig;
  file.intrinsics_std = result.rig.intrinsics_std;
  file.cam_overlaps = result.overlaps;
  if (!WriteRigFile(out, format, file, &why)) {
    std::cerr << "calibench: --out: " << why << "\n";
    return 3;
  }
  const std::vector<std::string> written = format == CameraFormat::kMrcal
                                               ? MrcalRigPaths(out, num_cameras)
                                               : std::vector<std::string>{out};
  for (const std::string& path : written) {
    std::cerr << "calibench: wrote " << path << " (" << ToString(format) << ")\n";
  }
  std::string rectified = args.rectified_path;
  if (rectified.empty()) {
    const fs::path out_path(out);
    rectified = (out_path.parent_path() / (out_path.stem().string() + "-rectified.png")).string();
  }
  // Best effort unless asked for: a rig whose cameras 0 and 1 cannot be rectified (they look apart)
  // or share no frame is calibrated all the same.
  const int rectified_status = WriteRectifiedPair(result, cameras, rectified);
  // The rig file is what was asked for: a page that cannot be written is a warning.
  CalibrationPageFiles page;
  if (!args.no_page && !WriteRigCalibrationPage(out, result, rectified, &page, &why)) {
    std::cerr << "calibench: warning: the calibration page was not written: " << why << "\n";
  } else if (!args.no_page) {
    std::cerr << "calibench: wrote " << page.markdown << " and " << page.figures.size()
              << " figures\n";
  }
  return args.rectified_path.empty() ? 0 : rectified_status;
}

}  // namespace calibench
