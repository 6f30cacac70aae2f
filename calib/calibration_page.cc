// The calibration page beside a camera file (calib/calibration_page.h).
#include "calib/calibration_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "calib/calibration_pictures.h"
#include "util/atomic_file.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

std::string Fixed(double v, int decimals) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, v);
  return text;
}

// The heatmap of an uncertainty map: a short title, and the colour bar topped at 4x the median
// (the lens extrapolated in a corner without corners can reach 50x it and would leave the whole
// region of the data one colour; the bar's arrow says where values pass it).
HeatmapOptions UncertaintyHeatmap(const UncertaintyMap& map, const std::string& what) {
  HeatmapOptions heat;
  heat.title = "Projection uncertainty (" + what + "), rays at infinity, 1 sigma";
  if (map.max_px > 4 * map.median_px) heat.max_value = 4 * map.median_px;
  return heat;
}

// How much of the field of view the corners reach, by angle from the optical axis.
struct FieldCoverage {
  double corners_max_deg = 0, image_max_deg = 0;
  double rings_covered = 0;  // Share of the 5-degree rings up to image_max_deg with a corner.
};
FieldCoverage FieldCoverageOf(const CameraIntrinsics& camera, int width, int height,
                              const std::vector<std::vector<Eigen::Vector2d>>& pixels) {
  FieldCoverage out;
  const auto angle_deg = [&](const Eigen::Vector2d& q, double* deg) {
    Eigen::Vector3d ray;
    if (!UnprojectToRay(camera, q, &ray)) return false;
    *deg = std::acos(std::clamp(ray.normalized().z(), -1.0, 1.0)) * 180.0 / M_PI;
    return true;
  };
  double deg = 0;
  for (int k = 0; k <= 100; ++k) {  // The image's border.
    const double s = k / 100.0;
    for (const Eigen::Vector2d& q :
         {Eigen::Vector2d(s * (width - 1), 0), Eigen::Vector2d(s * (width - 1), height - 1),
          Eigen::Vector2d(0, s * (height - 1)), Eigen::Vector2d(width - 1, s * (height - 1))}) {
      if (angle_deg(q, &deg)) out.image_max_deg = std::max(out.image_max_deg, deg);
    }
  }
  const int rings = std::max(1, static_cast<int>(std::ceil(out.image_max_deg / 5.0)));
  std::vector<bool> ring(rings, false);
  for (const std::vector<Eigen::Vector2d>& view : pixels) {
    for (const Eigen::Vector2d& q : view) {
      if (!angle_deg(q, &deg)) continue;
      out.corners_max_deg = std::max(out.corners_max_deg, deg);
      ring[std::min(rings - 1, static_cast<int>(deg / 5.0))] = true;
    }
  }
  out.rings_covered = static_cast<double>(std::count(ring.begin(), ring.end(), true)) / rings;
  return out;
}

}  // namespace

ViewResiduals ResidualsOf(const CalibrateResult& result) {
  ViewResiduals out;
  const CalibrateReport& report = result.calibration;
  const std::vector<int>& used = report.zhang.used_views;
  if (used.size() != report.ceres.cam_from_object.size()) return out;
  for (size_t k = 0; k < used.size(); ++k) {
    const int v = used[k];
    const View& view = result.data.views[v];
    out.names.push_back(static_cast<size_t>(v) < result.data.view_names.size()
                            ? result.data.view_names[v]
                            : "view " + std::to_string(v));
    out.pixels.emplace_back();
    out.residuals_px.emplace_back();
    const Rigid3& pose = report.ceres.cam_from_object[k];
    for (size_t i = 0; i < view.points.size(); ++i) {
      Eigen::Vector2d projected;
      if (!ProjectPoint(report.ceres.intrinsics, pose.rotation * view.points[i] + pose.translation,
                        &projected)) {
        continue;
      }
      out.pixels.back().push_back(view.pixels[i]);
      out.residuals_px.back().push_back(view.pixels[i] - projected);
    }
  }
  return out;
}

bool WriteCalibrationPage(const std::string& camera_path, const CalibrateResult& result,
                          const CrossValidation* cross_validation, CalibrationPageFiles* files,
                          std::string* why) {
  const CalibrateReport& report = result.calibration;
  if (!report.IsUsable()) {
    if (why) *why = camera_path + ": no usable calibration to draw";
    return false;
  }
  const fs::path camera(camera_path);
  const fs::path dir = camera.parent_path();
  const std::string stem = camera.stem().string();
  const auto beside = [&](const std::string& suffix) { return (dir / (stem + suffix)).string(); };
  const int width = result.data.image_width, height = result.data.image_height;
  const ViewResiduals residuals = ResidualsOf(result);
  std::vector<Eigen::Vector2d> all_pixels, all_residuals;
  std::vector<std::vector<double>> norms;
  for (size_t v = 0; v < residuals.pixels.size(); ++v) {
    all_pixels.insert(all_pixels.end(), residuals.pixels[v].begin(), residuals.pixels[v].end());
    all_residuals.insert(all_residuals.end(), residuals.residuals_px[v].begin(),
                         residuals.residuals_px[v].end());
    norms.emplace_back();
    for (const Eigen::Vector2d& r : residuals.residuals_px[v]) norms.back().push_back(r.norm());
  }
  const std::string model = report.camera.ModelName();
  std::ostringstream md;
  md << "# Calibration of " << camera.filename().string() << "\n\n";
  md << "Lens model " << model << ", " << residuals.names.size() << " views, " << all_pixels.size()
     << " corners, reprojection RMS " << Fixed(report.ceres.rms_reproj_px, 3)
     << " px (per corner), image " << width << " x " << height << " px.\n\n";
  files->figures.clear();
  if (report.uncertainty) {
    const CalibrationUncertainty& u = *report.uncertainty;
    const std::string region = WorstRegion(u.quoted_map.worst_std_px, nullptr);
    md << "## Where the calibration can be trusted\n\n"
       << "Projection uncertainty: how far (1 sigma, worst direction) the image of a distant point "
          "moves when the calibration is re-made from new images of the same kind. "
       << "Centre " << Fixed(u.quoted_map.centre_px, 3) << " px, median "
       << Fixed(u.quoted_map.median_px, 3) << " px, worst " << Fixed(u.quoted_map.max_px, 3)
       << " px (" << (region.empty() ? "-" : region) << "). Far from the corners (outside the "
       << "red dots) it grows: add views that put the target there.\n\n";
    md << "| figure | median (px) | from |\n|---|---:|---|\n"
       << "| formal | " << Fixed(u.formal.median_px, 3) << " | corner noise "
       << Fixed(u.quoted.sigma_px / u.scale, 3) << " px from the residuals, independent |\n";
    if (u.jackknife) {
      md << "| leave-one-view-out | " << Fixed(u.jackknife->median_px, 3) << " | the spread of "
         << residuals.names.size() << " calibrations each without one view ("
         << Fixed(u.jackknife_ratio, 2) << "x the formal) |\n";
    }
    md << "| **quoted** (drawn) | " << Fixed(u.quoted_map.median_px, 3) << " | "
       << (u.scale > 1 ? "the formal map scaled by " + Fixed(u.scale, 2) +
                             ": the views disagree more than independent noise explains"
                       : "the formal map (the jackknife does not exceed it)")
       << " |\n\n";
    HeatmapOptions heat = UncertaintyHeatmap(u.quoted_map, model);
    const std::string path = beside("-uncertainty.png");
    if (!WriteHeatmapPng(path, u.quoted_map.worst_std_px, all_pixels, heat, why)) return false;
    files->figures.push_back(path);
    md << "![projection uncertainty](" << stem << "-uncertainty.png)\n\n";
  } else {
    md << "No projection uncertainty: the calibration computed no covariance (the camera was "
          "evaluated, not fitted).\n\n";
  }
  if (cross_validation && cross_validation->ok) {
    const CameraComparison& c = cross_validation->comparison;
    md << "## Cross-validation\n\nThe views split in two halves ("
       << cross_validation->half_views[0] << " and " << cross_validation->half_views[1]
       << "), each calibrated alone. Their projections differ by a median " << Fixed(c.median_px, 3)
       << " px (max " << Fixed(c.max_px, 3) << " px, largest in the " << c.worst_region
       << ") after a rotation of " << Fixed(c.rotation_deg, 3) << " deg; "
       << (c.verdict == CameraComparison::Verdict::kAgree ? "they agree within their uncertainty"
                                                          : "they differ beyond their uncertainty")
       << " (" << Fixed(100 * c.within_fraction, 0) << " % of the field within "
       << Fixed(kAgreeSigmas, 0) << " sigma).\n\n";
    HeatmapOptions heat;
    heat.title = "Projection difference of the two halves' calibrations";
    const std::string path = beside("-cross-validation.png");
    if (!WriteHeatmapPng(path, c.difference_px, {}, heat, why)) return false;
    files->figures.push_back(path);
    md << "![cross-validation](" << stem << "-cross-validation.png)\n\n";
  } else if (cross_validation) {
    md << "Cross-validation not done: " << cross_validation->message << "\n\n";
  }
  if (!cross_validation || !cross_validation->ok) {
    std::error_code ec;  // A figure of an earlier run would stand beside this page.
    fs::remove(beside("-cross-validation.png"), ec);
  }
  md << "## Residuals\n\n";
  {
    const std::string path = beside("-residuals.png");
    if (!WriteResidualVectorsPng(path, width, height, all_pixels, all_residuals,
                                 "Residuals (measured - projected) of " + model, why)) {
      return false;
    }
    files->figures.push_back(path);
    md << "A pattern (vectors turning together, growing to the edge) is a lens the model does not "
          "fit; random directions are corner noise.\n\n![residual vectors]("
       << stem << "-residuals.png)\n\n";
  }
  if (!norms.empty()) {
    const std::string path = beside("-view-residuals.png");
    if (!WriteViewResidualsPng(path, residuals.names, norms, "Residuals per view", why)) {
      return false;
    }
    files->figures.push_back(path);
    md << "![residuals per view](" << stem << "-view-residuals.png)\n\n";
  }
  md << "## Coverage\n\n";
  {
    const std::string path = beside("-coverage.png");
    double covered = 0;
    if (!WriteCoveragePng(path, width, height, residuals.pixels, "Corners used, per view", &covered,
                          why)) {
      return false;
    }
    files->figures.push_back(path);
    const FieldCoverage field =
        FieldCoverageOf(report.ceres.intrinsics, width, height, residuals.pixels);
    md << "The corners cover " << Fixed(100 * covered, 0)
       << " % of the image's 10 x 10 cells. Cells without corners are where the lens is "
          "extrapolated. Of the field of view, they reach "
       << Fixed(field.corners_max_deg, 1) << " deg from the optical axis, the image "
       << Fixed(field.image_max_deg, 1) << " deg (its farthest pixel that the lens images), and "
       << Fixed(100 * field.rings_covered, 0)
       << " % of the 5-degree rings of angle from the axis up to there hold a corner.\n\n"
          "![coverage]("
       << stem << "-coverage.png)\n";
  }
  files->markdown = beside(".md");
  std::string reason;
  if (!WriteFileAtomically(files->markdown, md.str(), &reason)) {
    if (why) *why = reason;
    return false;
  }
  return true;
}

bool WriteRigCalibrationPage(const std::string& rig_path, const CalibrateRigResult& result,
                             const std::string& rectified_png, CalibrationPageFiles* files,
                             std::string* why) {
  if (!result.IsUsable()) {
    if (why) *why = rig_path + ": no usable rig calibration to draw";
    return false;
  }
  const fs::path rig_file(rig_path);
  const fs::path dir = rig_file.parent_path();
  const std::string stem = rig_file.stem().string();
  const CameraRig& rig = result.rig.rig;
  const int num_cameras = rig.NumCameras();
  files->figures.clear();
  std::ostringstream md;
  md << "# Calibration of the rig " << rig_file.filename().string() << "\n\n"
     << num_cameras << " cameras, " << result.frames.size() << " frames, joint RMS "
     << Fixed(result.rig.rms_reproj_px, 3) << " px over " << result.rig.num_points
     << " corners (noise sigma " << Fixed(result.rig.sigma_hat_px, 3) << " px).\n\n";
  md << "## The cameras in the rig\n\n| camera | baseline (mm) | direction std (deg) | rotation "
        "vector (deg) | rotation std x, y, z (deg) |\n|---|---:|---:|---|---|\n";
  for (int c = 1; c < num_cameras; ++c) {
    const RigPoseUncertainty& u = result.rig.pose_uncertainty[c];
    const Eigen::Vector3d r = rig.RelativeRotationDeg(c);
    md << "| " << c << " from 0 | " << Fixed(rig.BaselineM(c) * 1000.0, 3) << " +- "
       << Fixed(u.baseline_std_mm, 3) << " | " << Fixed(u.baseline_direction_std_deg, 4) << " | "
       << Fixed(r.x(), 4) << ", " << Fixed(r.y(), 4) << ", " << Fixed(r.z(), 4) << " | "
       << Fixed(u.rotation_std_deg.x(), 4) << ", " << Fixed(u.rotation_std_deg.y(), 4) << ", "
       << Fixed(u.rotation_std_deg.z(), 4) << " |\n";
  }
  md << "\n";
  for (const EpipolarErrors& e : result.epipolar) {
    md << "Epipolar error of cameras " << e.camera_a << " and " << e.camera_b << ": "
       << Fixed(e.rms_px, 3) << " px RMS over " << e.num_points << " shared corners.\n\n";
  }
  if (!rectified_png.empty() && fs::is_regular_file(rectified_png)) {
    md << "The first pair rectified (rows of the two images should meet the same scene points "
          "on each horizontal line):\n\n![rectified pair]("
       << fs::path(rectified_png).filename().string() << ")\n\n";
  }
  for (int c = 0; c < num_cameras; ++c) {
    const RigCamera& camera = rig.cameras[c];
    const std::string name = "camera " + std::to_string(c);
    const std::string prefix = stem + "-camera-" + std::to_string(c);
    // Joint residuals: each frame's view through cam_from_rig_c * rig_from_board_f.
    std::vector<std::vector<Eigen::Vector2d>> pixels;
    std::vector<Eigen::Vector2d> all_pixels, all_residuals;
    for (size_t f = 0; f < result.frames.size(); ++f) {
      const View& view = result.frames[f].views_by_camera[c];
      if (view.points.empty()) continue;
      pixels.emplace_back(view.pixels);
      const Rigid3 pose = camera.cam_from_rig * result.rig.rig_from_board[f];
      for (size_t i = 0; i < view.points.size(); ++i) {
        Eigen::Vector2d projected;
        if (!ProjectPoint(camera.intrinsics, pose * view.points[i], &projected)) continue;
        all_pixels.push_back(view.pixels[i]);
        all_residuals.push_back(view.pixels[i] - projected);
      }
    }
    md << "## " << name << " (" << ToString(camera.lens_model) << ", " << camera.image_width
       << " x " << camera.image_height << ", " << pixels.size() << " frames)\n\n";
    if (c < static_cast<int>(result.rig.projection.size()) && result.rig.projection[c].IsSet()) {
      const UncertaintyMap map = ProjectionUncertaintyMap(
          camera.intrinsics, result.rig.projection[c], camera.image_width, camera.image_height, {});
      md << "Projection uncertainty (rays at infinity, 1 sigma, formal: independent corner "
            "noise): centre "
         << Fixed(map.centre_px, 3) << " px, median " << Fixed(map.median_px, 3) << " px, worst "
         << Fixed(map.max_px, 3) << " px (" << WorstRegion(map.worst_std_px, nullptr)
         << "). On real images compare the jackknife std of the printout: corners of a frame "
            "share their errors and the formal figure is then too small.\n\n";
      const HeatmapOptions heat =
          UncertaintyHeatmap(map, name + ", " + std::string(ToString(camera.lens_model)));
      const std::string path = (dir / (prefix + "-uncertainty.png")).string();
      if (!WriteHeatmapPng(path, map.worst_std_px, all_pixels, heat, why)) return false;
      files->figures.push_back(path);
      md << "![" << name << " uncertainty](" << prefix << "-uncertainty.png)\n\n";
    }
    const std::string residuals = (dir / (prefix + "-residuals.png")).string();
    if (!WriteResidualVectorsPng(residuals, camera.image_width, camera.image_height, all_pixels,
                                 all_residuals, "Joint residuals, " + name, why)) {
      return false;
    }
    files->figures.push_back(residuals);
    const std::string coverage = (dir / (prefix + "-coverage.png")).string();
    double covered = 0;
    if (!WriteCoveragePng(coverage, camera.image_width, camera.image_height, pixels,
                          "Corners, " + name + ", per frame", &covered, why)) {
      return false;
    }
    files->figures.push_back(coverage);
    md << "Corners cover " << Fixed(100 * covered, 0) << " % of the image's 10 x 10 cells.\n\n"
       << "![" << name << " residuals](" << prefix << "-residuals.png)\n![" << name << " coverage]("
       << prefix << "-coverage.png)\n\n";
  }
  files->markdown = (dir / (stem + ".md")).string();
  std::string reason;
  if (!WriteFileAtomically(files->markdown, md.str(), &reason)) {
    if (why) *why = reason;
    return false;
  }
  return true;
}

}  // namespace calibench
