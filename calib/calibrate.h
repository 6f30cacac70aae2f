// Calibrating a camera from point files or detected images: an initialisation, then ceres refines
// (per-view board poses, the chosen lens model, optional skew) and reports standard deviations
// from its covariance (sigma estimated from the residuals). The initialisation: zhang
// (cv::calibrateCamera) for the radtan models; cv::fisheye::calibrate for pinhole-equi, or the wide
// start (batch/wide_init.h) when cv::fisheye does not fit; the wide start for unified, eucm and
// double-sphere, which OpenCV cannot start.
//
// With a given camera (`calibrate --init FILE`, any format of io/camera_io.h) the
// initial guess is that camera, each view's pose comes from it (batch/board_pose.h), and ceres
// either refines it (the file's lens model unless another is asked for) or, with evaluate_only,
// keeps every intrinsic fixed and moves only the poses: the per-image reprojection RMS of a given
// calibration on new images.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "batch/jackknife.h"
#include "batch/refine.h"
#include "batch/zhang.h"
#include "calib/calibration_uncertainty.h"
#include "calib/camera_file.h"
#include "calib/image_points.h"
#include "calib/point_data.h"

namespace calibench {

struct CalibrateOptions {
  LensModel model = LensModel::kPinholeK2;
  // The model chosen among the candidates instead (calibrate_camera.h; model_select.h); not with
  // init. CalibrateFromPoints ignores it.
  bool select_model = false;
  bool estimate_skew = false;
  std::optional<CameraFile> init;  // A given camera: the initial guess instead of zhang.
  std::string init_path;           // Its file, for the report.
  bool evaluate_only = false;      // With init: fix the intrinsics, estimate only the poses.
  // The leave-one-view-out std (batch/jackknife.h) beside the formal one: kAuto computes it for
  // at most kJackknifeAutoMaxViews views (each view costs one more refinement).
  enum class Jackknife { kAuto, kOn, kOff };
  Jackknife jackknife = Jackknife::kAuto;
  // CalibrateImages (calibrate_camera.h): at most this many re-fits of the corners through the
  // estimate (IterateCornersThroughTheLens); 0: none.
  int corner_iterations = 4;
  // False with *why when the options contradict each other (select_model or evaluate_only with
  // init / without init, negative corner_iterations).
  bool Check(std::string* why) const;
};
constexpr int kJackknifeAutoMaxViews = 30;
// The formal std is flagged when the jackknife's is this many times larger for a parameter.
constexpr double kJackknifeFlagRatio = 2.0;

struct CalibrateReport {
  // The initialisation: zhang's (or cv::fisheye's, or the wide start's: initial_name says which)
  // result, or (with init) the given camera with the poses found through it (intrinsics_std NaN,
  // rms_reproj_px at those poses before refinement).
  ZhangResult zhang;
  std::string initial_name = "zhang (OpenCV)";
  bool evaluated = false;  // The given camera was kept fixed (evaluate_only).
  RefineResult ceres;      // A failure's message names the view's file (PointData::view_names).
  // The leave-one-view-out std of ceres' intrinsics (AddJackknife), when computed.
  std::optional<JackknifeResult> jackknife;
  CameraFile camera;  // What camera.yaml holds (the ceres result).
  // Where in the image it can be trusted (calib/calibration_uncertainty.h); nullopt when the
  // refinement computed no covariance (evaluate-only) or the image size is unknown.
  std::optional<CalibrationUncertainty> uncertainty;
  bool IsUsable() const { return ceres.IsUsable(); }
};

CalibrateReport CalibrateFromPoints(const PointData& data, const CalibrateOptions& options);

// The jackknife std of a usable, refined (not evaluate_only) report of `data`, as
// options.jackknife asks; a jackknife that fails is kept with its reason (the report says it).
void AddJackknife(const PointData& data, const CalibrateOptions& options, CalibrateReport* report);

// The projection uncertainty of a usable report of `data` (calib/calibration_uncertainty.h), after
// AddJackknife (it scales by the jackknife when there is one), into report->uncertainty and the
// camera file's projection fields; nullopt without a covariance (evaluate-only).
void AddProjectionUncertainty(const PointData& data, const CalibrateOptions& options,
                              CalibrateReport* report);

// A given camera (`init`, read from `init_path`) fits images of `data`'s size: false with *why
// naming the file, its image_width / image_height and the images' size (from `images_dir`)
// otherwise. A camera file without a size (0) fits any.
bool CheckInitImageSize(const CameraFile& init, const std::string& init_path, const PointData& data,
                        const std::string& images_dir, std::string* why);

// A folder of images calibrated: the points, what each image gave, the tags found (kept for the
// re-fits through the lens) and the calibration.
struct ImageCalibration {
  PointData data;  // data.views[i] comes from images.images[used_index[i]].
  ImageFolderReport images;
  std::vector<int> used_index;
  ImageDetectionCache detections;
  CalibrateReport report;
};

// calibrate --images through a lens that distorts: the corners of every image are fitted again
// through the current estimate (aprilgrid: the lens-aware photometric fit,
// detect/photometric_fit.h, the tags' edges bending as the lens bends them; checkerboard: the
// X-junctions in a plane where the board's lines are straight, detect/x_junction.h; what the
// detector found before is reused, state->detections) and the camera is recalibrated (from scratch,
// as the first time: started from the previous camera, Levenberg-Marquardt was measured to stop in
// a worse minimum on a 160 deg fisheye), until f.ku moves by less than kCornerIterationTol of its
// std or after `max_iterations` re-fits. Each pass prints one line to `log`: f.ku +- std, RMS, and
// the RMS and largest move of the corners matched between passes. Before each pass on an aprilgrid
// the change it could make is predicted (the largest change in how the new estimate bends a tag's
// edges against the camera the corners were fitted through, EdgeBendChangePx, and the f.ku move
// that bounds, calibrate.cc PredictRefit); a pass predicted to move f.ku by less than
// kCornerIterationTol of its std is not run, and the log says so. `images`: how the images are read
// (threads, refinement); its camera, lens and detection_cache are set per pass. *state (its report
// usable) is replaced by the last usable pass.
constexpr double kCornerIterationTol = 0.1;
void IterateCornersThroughTheLens(const std::string& dir, const CalibrationTarget& target,
                                  const ImagePointOptions& images, const CalibrateOptions& options,
                                  int max_iterations, ImageCalibration* state, std::ostream& log);

// A calibration whose reprojection RMS exceeds this is flagged (and cv::fisheye's start is not
// trusted): detected corners are good to ~0.1 px and real lenses fit to < 0.5 px with a matching
// model, so > 1 px means the target geometry (spacing, size) or the lens model does not match the
// images.
constexpr double kHighReprojectionPx = 1.0;

}  // namespace calibench
