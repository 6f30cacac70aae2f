#include "calib/calibrate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include "batch/board_pose.h"
#include "batch/wide_init.h"
#include "detect/tangent_plane.h"

namespace calibench {

namespace {

// The given camera as the initialisation: each view's pose through it (views whose pose fails are
// left out, as zhang leaves out views with too few points), the RMS at those poses.
ZhangResult InitialiseFromCamera(const std::vector<View>& views, const CameraIntrinsics& camera) {
  const SummaryClock clock;
  ZhangResult result;
  result.intrinsics = camera;
  result.intrinsics_std.fill(std::nan(""));
  double sum_sq = 0.0;
  long count = 0;
  std::string first_failure;
  for (size_t v = 0; v < views.size(); ++v) {
    Rigid3 pose;
    std::string why;
    if (!BoardPoseFromIntrinsics(views[v], camera, &pose, &why)) {
      if (first_failure.empty()) first_failure = "view " + std::to_string(v) + ": " + why;
      continue;
    }
    double view_sq = 0.0;
    if (!ViewSquaredErrorPx2(views[v], camera, pose, &view_sq)) {
      if (first_failure.empty())
        first_failure = "view " + std::to_string(v) + ": behind the camera";
      continue;
    }
    result.used_views.push_back(static_cast<int>(v));
    result.cam_from_board.push_back(pose);
    sum_sq += view_sq;
    count += static_cast<long>(views[v].points.size());
  }
  if (result.used_views.empty()) {
    return clock.Finish(&result, MethodStatus::kFailed, "no view's pose: " + first_failure);
  }
  result.rms_reproj_px = std::sqrt(sum_sq / std::max(1L, count));
  return clock.Finish(&result, MethodStatus::kOk,
                      first_failure.empty() ? "" : "skipped " + first_failure);
}

WideInitResult WideStart(const PointData& data, LensModel model) {
  WideInitOptions wide;
  wide.model = model;
  wide.image_width = data.image_width;
  wide.image_height = data.image_height;
  return InitializeWideCamera(data.views, wide);
}

// The initialisation without a given camera. zhang (cv::calibrateCamera) for radtan; for the
// equidistant fisheye cv::fisheye::calibrate, and the wide start when that fails (it does on
// partial boards far off axis: it then returns its start) and the wide start fits better; the
// wide start for the omnidirectional families, which OpenCV cannot start.
ZhangResult StartFromScratch(const PointData& data, LensModel model, std::string* initial_name) {
  const LensFamily family = FamilyOf(model);
  if (!InfoOf(family).zhang_starts) {
    *initial_name = "wide start";
    return FromWideStart(WideStart(data, model));
  }
  ZhangOptions zhang_options;
  zhang_options.model = model;
  zhang_options.image_width = data.image_width;
  zhang_options.image_height = data.image_height;
  ZhangResult zhang = CalibrateZhang(data.views, zhang_options);
  if (family == LensFamily::kRadTan) return zhang;
  *initial_name = "cv::fisheye";
  const bool zhang_ok = zhang.IsUsable() && zhang.used_views.size() == data.views.size() &&
                        zhang.rms_reproj_px < kHighReprojectionPx;
  if (zhang_ok) return zhang;
  const WideInitResult wide = WideStart(data, model);
  if (!wide.IsUsable() && !zhang.IsUsable()) zhang.message += "; " + wide.message;
  if (!wide.IsUsable() || (zhang.IsUsable() && wide.rms_reproj_px >= zhang.rms_reproj_px)) {
    return zhang;
  }
  char opencv[64];
  std::snprintf(opencv, sizeof(opencv), "RMS %.4g px", zhang.rms_reproj_px);
  ZhangResult start = FromWideStart(wide);
  start.message = "cv::fisheye::calibrate did not fit (" +
                  (zhang.IsUsable() ? std::string(opencv) : zhang.message) + "): " + wide.message;
  *initial_name = "wide start";
  return start;
}

// The views the initialisation kept, in its order (that of ceres' poses).
std::vector<View> UsedViews(const PointData& data, const ZhangResult& start) {
  std::vector<View> used;
  for (int v : start.used_views) used.push_back(data.views[v]);
  return used;
}

}  // namespace

bool CalibrateOptions::Check(std::string* why) const {
  std::string reason;
  if (select_model && init) {
    reason = "select_model fits every candidate model from scratch; init gives one camera";
  } else if (evaluate_only && !init) {
    reason = "evaluate_only needs init (the calibration to evaluate)";
  } else if (corner_iterations < 0) {
    reason = "corner_iterations must be >= 0";
  }
  if (why) *why = reason;
  return reason.empty();
}

CalibrateReport CalibrateFromPoints(const PointData& data, const CalibrateOptions& options) {
  CalibrateReport report;
  if (options.init) {
    report.initial_name = "init (" + options.init->ModelName() + ")";
    report.zhang = InitialiseFromCamera(data.views, options.init->intrinsics);
  } else {
    report.zhang = StartFromScratch(data, options.model, &report.initial_name);
  }
  if (!report.zhang.IsUsable()) {
    report.ceres.status = MethodStatus::kFailed;
    report.ceres.message = report.initial_name + " initialisation failed: " + report.zhang.message;
    return report;
  }
  const std::vector<View> used = UsedViews(data, report.zhang);
  RefineOptions refine;
  refine.model = options.model;
  refine.estimate_skew = options.estimate_skew;
  refine.fix_intrinsics = options.init && options.evaluate_only;
  report.evaluated = refine.fix_intrinsics;
  for (int v : report.zhang.used_views) {  // Failures name the input's view.
    refine.view_names.push_back(v < static_cast<int>(data.view_names.size())
                                    ? data.view_names[v]
                                    : "view " + std::to_string(v));
  }
  report.ceres =
      RefineCalibration(used, report.zhang.intrinsics, report.zhang.cam_from_board, refine);
  CameraFile& c = report.camera;
  c.intrinsics = report.ceres.intrinsics;
  c.intrinsics_std = report.ceres.intrinsics_std;
  c.image_width = data.image_width;
  c.image_height = data.image_height;
  c.rms_reproj_px = report.ceres.rms_reproj_px;
  c.view_rms_px = report.ceres.view_rms_px;
  c.lens_model = options.model;
  c.estimate_skew = options.estimate_skew;
  return report;
}

void AddJackknife(const PointData& data, const CalibrateOptions& options, CalibrateReport* report) {
  report->jackknife.reset();
  const int views = static_cast<int>(report->zhang.used_views.size());
  const bool wanted =
      options.jackknife == CalibrateOptions::Jackknife::kOn ||
      (options.jackknife == CalibrateOptions::Jackknife::kAuto && views <= kJackknifeAutoMaxViews);
  if (!wanted || !report->IsUsable()) return;
  if (report->evaluated) {
    if (options.jackknife == CalibrateOptions::Jackknife::kOn) {
      report->jackknife = JackknifeResult();
      report->jackknife->message =
          "the given camera is kept fixed (--evaluate): no intrinsic moves";
    }
    return;
  }
  const std::vector<View> used = UsedViews(data, report->zhang);
  JackknifeOptions jackknife;
  jackknife.view_ids = report->zhang.used_views;  // Failures name the input's view.
  jackknife.refine.model = options.model;
  jackknife.refine.estimate_skew = options.estimate_skew;
  report->jackknife = JackknifeIntrinsics(used, report->ceres, jackknife);
}

void AddProjectionUncertainty(const PointData& data, const CalibrateOptions& options,
                              CalibrateReport* report) {
  RefineOptions refine;  // As the refinement's (CalibrateFromPoints) and the jackknife's.
  refine.model = options.model;
  refine.estimate_skew = options.estimate_skew;
  report->uncertainty =
      AssessProjectionUncertainty(UsedViews(data, report->zhang), refine, report->ceres,
                                  report->jackknife, data.image_width, data.image_height, {});
  if (report->uncertainty) {
    report->camera.projection = report->uncertainty->quoted;
    report->camera.projection_scale = report->uncertainty->scale;
    report->camera.projection_source = report->uncertainty->jackknife ? "jackknife" : "formal";
  }
}

namespace {

// The corners of two detections of the same images matched by image and target point: the RMS
// and the largest move (px), and how many matched.
struct CornerMoves {
  double rms_px = 0, max_px = 0;
  long matched = 0;
};
CornerMoves CompareCorners(const PointData& a, const std::vector<int>& a_index,
                           const ImageFolderReport& a_images, const PointData& b,
                           const std::vector<int>& b_index, const ImageFolderReport& b_images) {
  std::map<std::string, const View*> by_file;
  for (size_t i = 0; i < a.views.size(); ++i)
    by_file[a_images.images[a_index[i]].file] = &a.views[i];
  CornerMoves moves;
  double sum_sq = 0;
  for (size_t i = 0; i < b.views.size(); ++i) {
    const auto it = by_file.find(b_images.images[b_index[i]].file);
    if (it == by_file.end()) continue;
    std::map<std::array<double, 3>, Eigen::Vector2d> pixel_of;
    const View& old_view = *it->second;
    for (size_t k = 0; k < old_view.points.size(); ++k) {
      const Eigen::Vector3d& p = old_view.points[k];
      pixel_of[{p.x(), p.y(), p.z()}] = old_view.pixels[k];
    }
    for (size_t k = 0; k < b.views[i].points.size(); ++k) {
      const Eigen::Vector3d& p = b.views[i].points[k];
      const auto match = pixel_of.find({p.x(), p.y(), p.z()});
      if (match == pixel_of.end()) continue;
      const double d = (b.views[i].pixels[k] - match->second).norm();
      sum_sq += d * d;
      moves.max_px = std::max(moves.max_px, d);
      ++moves.matched;
    }
  }
  if (moves.matched > 0) moves.rms_px = std::sqrt(sum_sq / static_cast<double>(moves.matched));
  return moves;
}

// What re-fitting the corners through `next` could change: the largest change of a tag's edges
// between the camera the corners were fitted through (`fitted_through`; nullptr: a homography) and
// `next` (EdgeBendChangePx over every tag found), and its effect on f.ku. Corners moved by at most
// delta move f.ku, at most, as a scale about the principal point would: the least-squares scale
// of moves d_i at radii r_i is sum r_i d_i / sum r_i^2 <= delta / r_rms (Cauchy-Schwarz), r_rms the
// corners' RMS distance from (u0, v0); so f.ku moves by at most f.ku delta / r_rms. NaN when any
// tag's change is unknown.
struct RefitEffect {
  double bend_px = std::nan(""), fku_move_px = std::nan("");
};
RefitEffect PredictRefit(const ImageDetectionCache& tags, const CameraIntrinsics* fitted_through,
                         const CameraIntrinsics& next, const PointData& data) {
  RefitEffect effect;
  if (!tags.filled) return effect;
  double bend = 0;
  for (const FoundTags& found : tags.per_image) {
    for (const TagDetection& tag : found.tags) {
      const double change = EdgeBendChangePx(fitted_through, next, tag.corners);
      if (!std::isfinite(change)) return effect;
      bend = std::max(bend, change);
    }
  }
  double sum_sq = 0;
  long count = 0;
  const Eigen::Vector2d centre(next.u0_px, next.v0_px);
  for (const View& view : data.views) {
    for (const Eigen::Vector2d& pixel : view.pixels) sum_sq += (pixel - centre).squaredNorm();
    count += static_cast<long>(view.pixels.size());
  }
  if (count == 0 || !(sum_sq > 0)) return effect;
  effect.bend_px = bend;
  effect.fku_move_px = next.fku_px * bend / std::sqrt(sum_sq / static_cast<double>(count));
  return effect;
}

}  // namespace

bool CheckInitImageSize(const CameraFile& init, const std::string& init_path, const PointData& data,
                        const std::string& images_dir, std::string* why) {
  if (init.image_width <= 0 || init.image_height <= 0) return true;
  if (init.image_width == data.image_width && init.image_height == data.image_height) return true;
  if (why) {
    *why = init_path + ": image_width / image_height " + std::to_string(init.image_width) + " x " +
           std::to_string(init.image_height) + " px, but the images in " + images_dir + " are " +
           std::to_string(data.image_width) + " x " + std::to_string(data.image_height) +
           " px: the camera was calibrated for another image size";
  }
  return false;
}

void IterateCornersThroughTheLens(const std::string& dir, const CalibrationTarget& target,
                                  const ImagePointOptions& images, const CalibrateOptions& options,
                                  int max_iterations, ImageCalibration* state, std::ostream& log) {
  char line[256];
  auto print = [&](const char* what, const CalibrateReport& r, const CornerMoves* moves) {
    std::snprintf(line, sizeof(line), "corners %-22s f.ku %.4f +- %.4f px, RMS %.4f px", what,
                  r.camera.intrinsics.fku_px, r.ceres.intrinsics_std[0], r.camera.rms_reproj_px);
    log << line;
    if (moves) {
      std::snprintf(line, sizeof(line), "; %ld corners moved by %.4f px RMS (max %.4f px)",
                    moves->matched, moves->rms_px, moves->max_px);
      log << line;
    }
    log << "\n";
  };
  if (!state->report.IsUsable()) return;
  const bool aprilgrid = target.type == CalibrationTarget::Type::kAprilGrid;
  print(options.init ? "through --init's lens:"
        : aprilgrid  ? "through a homography:"
                     : "in the image:",
        state->report, nullptr);
  // The camera the current corners were fitted through (none: a homography in pixels).
  std::optional<CameraIntrinsics> fitted_through;
  if (options.init) fitted_through = options.init->intrinsics;
  for (int pass = 1; pass <= max_iterations; ++pass) {
    const CameraIntrinsics& camera = state->report.camera.intrinsics;
    // A checkerboard's corners have no prediction: the pass is run.
    const RefitEffect effect =
        aprilgrid ? PredictRefit(state->detections, fitted_through ? &*fitted_through : nullptr,
                                 camera, state->data)
                  : RefitEffect();
    const double tolerance_px = kCornerIterationTol * state->report.ceres.intrinsics_std[0];
    if (effect.fku_move_px < tolerance_px) {
      std::snprintf(line, sizeof(line),
                    "corners through the lens, pass %d: not needed: the estimate bends the tags' "
                    "edges at most %.5f px away from the corners' fit, which moves f.ku by at most "
                    "%.5f px (< %.1f std = %.5f px)\n",
                    pass, effect.bend_px, effect.fku_move_px, kCornerIterationTol, tolerance_px);
      log << line;
      break;
    }
    // Its detections stay in state->detections (the cache) until it replaces *state.
    ImageCalibration next;
    std::string why;
    ImagePointOptions image_options = images;
    image_options.lens = FamilyOf(options.model);
    image_options.camera = state->report.camera.intrinsics;
    image_options.detection_cache = &state->detections;
    if (!LoadImagePoints(dir, target, &next.data, &next.images, &next.used_index, &why,
                         image_options)) {
      log << "corners through the lens: pass " << pass << " failed (" << why
          << "); keeping the previous calibration\n";
      break;
    }
    fitted_through = camera;
    next.report = CalibrateFromPoints(next.data, options);
    if (!next.report.IsUsable()) {
      log << "corners through the lens: pass " << pass
          << " gave no usable calibration; keeping the previous one\n";
      break;
    }
    const CornerMoves moves = CompareCorners(state->data, state->used_index, state->images,
                                             next.data, next.used_index, next.images);
    const double step =
        std::abs(next.report.camera.intrinsics.fku_px - state->report.camera.intrinsics.fku_px);
    const double std_fku = next.report.ceres.intrinsics_std[0];
    next.detections = std::move(state->detections);
    *state = std::move(next);
    print(("through the lens, pass " + std::to_string(pass) + ":").c_str(), state->report, &moves);
    if (!(step >= kCornerIterationTol * std_fku)) break;  // Also stops on a NaN std.
  }
}

}  // namespace calibench
