#include "calib/calibrate_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace calibench {

std::string FormatCalibrateReport(const CalibrateResult& result) {
  // Refused before any fit (bad images, a camera for another size, options that fail Check).
  const bool refused = result.status == CalibrateResult::Status::kBadImages ||
                       result.status == CalibrateResult::Status::kBadInit ||
                       (!result.selection && result.calibration.ceres.message.empty() &&
                        !result.calibration.ceres.IsUsable() && !result.message.empty());
  if (refused) return "calibration refused: " + result.message + "\n";
  std::string text;
  if (result.selection) {
    text += FormatModelSelection(*result.selection) + "\n";
    if (!result.selection->IsUsable()) return text;
  }
  text += FormatCalibrateReport(result.calibration, result.data);
  if (result.images)
    text += FormatImageReport(*result.images, result.used_index, result.calibration);
  return text;
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
  if (report.uncertainty) out << FormatProjectionUncertainty(*report.uncertainty);
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

}  // namespace calibench
