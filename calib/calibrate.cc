#include "calib/calibrate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

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
  if (family != LensFamily::kRadTan && family != LensFamily::kEquidistant) {
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

std::string FormatCalibrateReport(const CalibrateReport& report, const PointData& data) {
  std::ostringstream out;
  char line[200];
  out << "data: " << data.format << ", " << data.views.size() << " views, "
      << (data.views.empty() ? 0 : data.views[0].points.size()) << " points per view\n";
  if (!report.ceres.IsUsable()) {
    out << "calibration failed: " << report.ceres.message << "\n";
    if (report.zhang.IsUsable()) {
      const CameraIntrinsics& z = report.zhang.intrinsics;
      std::snprintf(line, sizeof(line),
                    "from %s: f (%.3f, %.3f), c (%.3f, %.3f), k1 %.6f, rms_reproj_px %.4f\n",
                    report.initial_name.c_str(), z.fku_px, z.fkv_px, z.u0_px, z.v0_px, z.k1,
                    report.zhang.rms_reproj_px);
      out << line;
    }
    return out.str();
  }
  const CameraIntrinsics &k = report.ceres.intrinsics, &z = report.zhang.intrinsics;
  const double* s = report.ceres.intrinsics_std.data();
  const bool jack = report.jackknife && report.jackknife->IsUsable();
  const double deg = 180.0 / M_PI;
  out << (report.evaluated ? "parameter        given camera (fixed)          "
                           : "parameter        ceres (+- 1 std)              ")
      << (jack ? "jackknife std  " : "") << report.initial_name << "\n";
  const std::array<const char*, 10>& names = ParamNames(k.family);
  struct Row {
    const char* name;
    double ours, std, jack_std, opencv;
  };
  const std::array<double, 10> ours = k.Params();
  const CameraIntrinsics z_same = z.family == k.family ? z : CameraIntrinsics();
  const std::array<double, 10> theirs = z_same.Params();
  std::vector<Row> rows;
  for (int i = 0; i < 10; ++i) {
    if (std::string(names[i]) == "-") continue;
    const double unit = i == 2 ? deg : 1.0;
    rows.push_back({names[i], i == 2 ? k.phi_deg : ours[i], s[i] * unit,
                    jack ? report.jackknife->intrinsics_std[i] * unit : std::nan(""),
                    i == 2 ? z_same.phi_deg : theirs[i]});
  }
  std::string understated;  // Parameters whose jackknife std exceeds the formal one.
  double worst_ratio = 0;
  for (const Row& r : rows) {
    char jack_column[32] = "";
    if (jack && std::isfinite(r.jack_std)) {
      std::snprintf(jack_column, sizeof(jack_column), "%14.6f ", r.jack_std);
    } else if (jack) {
      std::snprintf(jack_column, sizeof(jack_column), "%14s ", "");
    }
    if (std::isfinite(r.std)) {
      std::snprintf(line, sizeof(line), "%-10s %14.6f +- %-12.6f %s%14.6f\n", r.name, r.ours, r.std,
                    jack_column, r.opencv);
      if (std::isfinite(r.jack_std) && r.jack_std > kJackknifeFlagRatio * r.std) {
        understated += (understated.empty() ? "" : ", ") + std::string(r.name);
        worst_ratio = std::max(worst_ratio, r.jack_std / r.std);
      }
    } else {
      // No formal std: the parameter is fixed, or sat on a bound in the full fit (then the refits
      // may move it: its jackknife std is shown).
      std::snprintf(line, sizeof(line), "%-10s %14.6f %-16s%s%14.6f\n", r.name, r.ours,
                    std::isfinite(r.jack_std) ? "(no formal std)" : "(fixed)", jack_column,
                    r.opencv);
    }
    out << line;
  }
  if (report.jackknife && !report.jackknife->IsUsable()) {
    out << "jackknife: not computed: " << report.jackknife->message << "\n";
  } else if (jack) {
    std::snprintf(line, sizeof(line),
                  "jackknife std: the spread of %d calibrations each leaving one view out "
                  "(%.1f ms)\n",
                  report.jackknife->num_views, report.jackknife->wall_ms);
    out << line;
    if (!understated.empty()) {
      std::snprintf(line, sizeof(line), "%.1f", worst_ratio);
      out << "warning: the jackknife std exceeds the formal std by up to " << line << "x ("
          << understated
          << "): the views disagree more than independent pixel noise explains (errors shared "
             "by a view's corners, a lens model that does not fit, or too few views); quote the "
             "jackknife std\n";
    }
  }
  std::snprintf(line, sizeof(line), "rms_reproj_px (per point): ceres %.5f, %s %.5f\n",
                report.ceres.rms_reproj_px, report.initial_name.c_str(),
                report.zhang.rms_reproj_px);
  out << line << "per-view rms_reproj_px:";
  for (double r : report.ceres.view_rms_px) {
    std::snprintf(line, sizeof(line), " %.4f", r);
    out << line;
  }
  std::snprintf(line, sizeof(line), "\ntime: %s %.1f ms, ceres %.1f ms (%ld iterations)\n",
                report.initial_name.c_str(), report.zhang.wall_ms, report.ceres.wall_ms,
                report.ceres.iterations);
  out << line;
  if (!report.zhang.message.empty()) out << "note: " << report.zhang.message << "\n";
  if (!report.ceres.message.empty()) out << "note: ceres: " << report.ceres.message << "\n";
  return out.str();
}

std::string FormatImageReport(const ImageFolderReport& images, const std::vector<int>& used_index,
                              const CalibrateReport& report) {
  std::vector<double> view_rms(images.images.size(), -1.0);
  if (report.ceres.IsUsable()) {
    for (size_t i = 0; i < report.ceres.view_rms_px.size(); ++i) {
      view_rms[used_index[report.zhang.used_views[i]]] = report.ceres.view_rms_px[i];
    }
  }
  std::vector<double> sorted = report.ceres.view_rms_px;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  std::ostringstream out;
  char line[256];
  out << "image                          points  view_rms_px  note\n";
  int outliers = 0;
  for (size_t i = 0; i < images.images.size(); ++i) {
    const ImageResult& r = images.images[i];
    std::string note = r.used ? r.reason : "skipped: " + r.reason;
    std::string rms = "-";
    if (view_rms[i] >= 0) {
      std::snprintf(line, sizeof(line), "%.4f", view_rms[i]);
      rms = line;
      if (view_rms[i] > kOutlierFactor * median) {
        note += "; OUTLIER (> 3x median view RMS: re-take or drop this image)";
        ++outliers;
      }
    } else if (r.used) {
      note += "; not used by the calibration";
    }
    std::snprintf(line, sizeof(line), "%-30s %6d  %11s  %s\n", r.file.c_str(), r.points,
                  rms.c_str(), note.c_str());
    out << line;
  }
  out << images.used << " of " << images.images.size() << " images used; " << outliers
      << " outlier view(s)\n";
  if (images.tags_possible > 0) {
    std::snprintf(line, sizeof(line),
                  "aprilgrid: %ld of %ld possible tags detected (detection rate %.3f), %ld ids not "
                  "on the grid\n",
                  images.tags_detected, images.tags_possible, images.DetectionRate(),
                  images.unknown_tags);
    out << line;
    if (images.DetectionRate() < kLowDetectionRate) {
      out << "WARNING: low detection rate: check tagFamily, codeOffset and tagCols / tagRows of "
             "the target YAML against the printed target\n";
    }
  }
  if (report.ceres.IsUsable() && report.ceres.rms_reproj_px > kHighReprojectionPx) {
    std::snprintf(line, sizeof(line),
                  "WARNING: reprojection RMS %.3f px > %.1f px: the target geometry does not fit "
                  "the images (check tagSize / tagSpacing or the board spacings and size)\n",
                  report.ceres.rms_reproj_px, kHighReprojectionPx);
    out << line;
  }
  return out.str();
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
