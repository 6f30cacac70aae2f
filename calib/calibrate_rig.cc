#include "calib/calibrate_rig.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "calib/calibration_pictures.h"

namespace calibench {

namespace {

std::string CameraName(const CalibrateRigResult& result, int c) {
  if (c < static_cast<int>(result.rig.rig.cameras.size()) &&
      !result.rig.rig.cameras[c].name.empty()) {
    return result.rig.rig.cameras[c].name;
  }
  return "cam" + std::to_string(c);
}

std::string FrameName(const CalibrateRigResult& result, int f) {
  if (f < static_cast<int>(result.frame_names.size()) && !result.frame_names[f].empty()) {
    return result.frame_names[f];
  }
  return "frame " + std::to_string(f);
}

// The per-camera options of camera c.
CalibrateOptions CameraOptions(const CalibrateRigOptions& options, int c) {
  CalibrateOptions camera;
  if (!options.models.empty()) {  // Empty with select_model: each camera's is chosen.
    camera.model = options.models.size() == 1 ? options.models[0] : options.models[c];
  }
  camera.select_model = options.select_model;
  camera.estimate_skew = options.estimate_skew;
  camera.corner_iterations = options.corner_iterations;
  camera.jackknife = CalibrateOptions::Jackknife::kOff;
  if (options.init) {
    const RigCamera& given = options.init->cameras[c];
    CameraFile file;
    file.intrinsics = given.intrinsics;
    file.intrinsics_std.fill(std::nan(""));
    file.image_width = given.image_width;
    file.image_height = given.image_height;
    file.lens_model = given.lens_model;
    camera.init = file;
    camera.init_path = options.init_path;
    camera.model = given.lens_model;
    // The board poses through the given camera; the rig solve refines (or keeps) it.
    camera.evaluate_only = true;
    camera.corner_iterations = 0;
  }
  return camera;
}

// False with *why when the model list does not fit `num_cameras`, or the given rig has another
// number of cameras.
bool CheckCameraCount(const CalibrateRigOptions& options, int num_cameras, std::string* why) {
  if (num_cameras < 2) {
    *why = "a rig needs at least 2 cameras (one --images per camera), got " +
           std::to_string(num_cameras);
    return false;
  }
  if (options.init && options.init->NumCameras() != num_cameras) {
    *why = options.init_path + ": the given rig has " + std::to_string(options.init->NumCameras()) +
           " cameras, the images " + std::to_string(num_cameras);
    return false;
  }
  if (!options.select_model && options.models.size() != 1 &&
      static_cast<int>(options.models.size()) != num_cameras) {
    *why = "--model: " + std::to_string(options.models.size()) + " models for " +
           std::to_string(num_cameras) + " cameras: give one for all or one per camera";
    return false;
  }
  return true;
}

// rig_from_board of each frame from the given rig and the cameras' board poses: the pose of the
// camera that saw most corners of the frame.
std::vector<Rigid3> FramePosesThroughRig(const CalibrateRigResult& result, const CameraRig& rig) {
  std::vector<Rigid3> rig_from_board(result.frames.size());
  for (size_t f = 0; f < result.frames.size(); ++f) {
    size_t most = 0;
    for (int c = 0; c < rig.NumCameras(); ++c) {
      const int v = result.view_of_frame[f][c];
      if (v < 0) continue;
      const size_t n = result.frames[f].views_by_camera[c].points.size();
      if (n <= most) continue;
      most = n;
      rig_from_board[f] = rig.cameras[c].cam_from_rig.Inverse() *
                          result.cameras[c].calibration.ceres.cam_from_object[v];
    }
  }
  return rig_from_board;
}

// Steps 2-4 of the header comment on result->cameras (each camera alone) and view_of_frame.
void SolveRigFrom(const CalibrateRigOptions& options, CalibrateRigResult* result);

}  // namespace

bool CalibrateRigOptions::Check(std::string* why) const {
  const auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (models.empty() && !select_model) return fail("no lens model given");
  if (evaluate_only && !init) return fail("evaluate_only needs a given rig (init)");
  if (select_model && init) return fail("the model is the given rig's: select_model with init");
  if (corner_iterations < 0) return fail("corner_iterations must be >= 0");
  return true;
}

CalibrateRigResult CalibrateRigPoints(const RigPointData& data,
                                      const CalibrateRigOptions& options) {
  CalibrateRigResult result;
  const int num_cameras = static_cast<int>(data.cameras.size());
  if (!options.Check(&result.message) || !CheckCameraCount(options, num_cameras, &result.message)) {
    return result;
  }
  for (int c = 0; c < num_cameras; ++c) {
    result.cameras.push_back(CalibratePoints(data.cameras[c], CameraOptions(options, c)));
  }
  result.view_of_frame = data.view_of_frame;
  result.frame_names = data.frame_names;
  result.frame_names.resize(data.view_of_frame.size());
  result.rig.rig.cameras.resize(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    result.rig.rig.cameras[c].name = c < static_cast<int>(data.camera_names.size())
                                         ? data.camera_names[c]
                                         : "cam" + std::to_string(c);
  }
  SolveRigFrom(options, &result);
  return result;
}

RigPointData RigPointDataFromFrames(const std::vector<RigFrame>& frames, const CameraRig& rig) {
  RigPointData data;
  const int num_cameras = rig.NumCameras();
  data.cameras.resize(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    data.cameras[c].format = "synthetic";
    data.cameras[c].image_width = rig.cameras[c].image_width;
    data.cameras[c].image_height = rig.cameras[c].image_height;
    data.camera_names.push_back(rig.cameras[c].name);
  }
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string name = frames[f].name.empty() ? "frame " + std::to_string(f) : frames[f].name;
    data.frame_names.push_back(name);
    std::vector<int> views(num_cameras, -1);
    for (int c = 0; c < num_cameras && c < static_cast<int>(frames[f].views_by_camera.size());
         ++c) {
      const View& view = frames[f].views_by_camera[c];
      if (view.points.empty()) continue;
      views[c] = static_cast<int>(data.cameras[c].views.size());
      data.cameras[c].views.push_back(view);
      data.cameras[c].view_names.push_back(name);
    }
    data.view_of_frame.push_back(views);
  }
  return data;
}

CalibrateRigResult CalibrateRigImages(const std::vector<RigCameraImages>& cameras,
                                      const CalibrationTarget& target,
                                      const ImagePointOptions& images,
                                      const CalibrateRigOptions& options, std::ostream* log) {
  CalibrateRigResult result;
  const int num_cameras = static_cast<int>(cameras.size());
  if (!options.Check(&result.message) || !CheckCameraCount(options, num_cameras, &result.message)) {
    return result;
  }
  const size_t num_frames = cameras[0].files_by_frame.size();
  for (const RigCameraImages& camera : cameras) {
    if (camera.files_by_frame.size() != num_frames) {
      result.message = camera.source + ": " + std::to_string(camera.files_by_frame.size()) +
                       " frames where the first camera has " + std::to_string(num_frames);
      return result;
    }
  }
  result.rig.rig.cameras.resize(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    const RigCameraImages& camera = cameras[c];
    result.rig.rig.cameras[c].name = camera.source;
    ImagePointOptions camera_images = images;
    for (const std::string& file : camera.files_by_frame) {
      if (!file.empty()) camera_images.files.push_back(file);
    }
    if (camera_images.files.empty()) {
      result.status = CalibrateRigResult::Status::kBadImages;
      result.message = camera.source + ": no image of this camera is paired with another's";
      return result;
    }
    if (log) *log << "camera " << c << " (" << camera.source << "):\n";
    result.cameras.push_back(
        CalibrateImages(camera.dir, target, camera_images, CameraOptions(options, c), log));
    const CalibrateResult& alone = result.cameras.back();
    if (!alone.IsUsable()) {
      result.status = alone.status == CalibrateResult::Status::kBadInit
                          ? CalibrateRigResult::Status::kBadInit
                          : CalibrateRigResult::Status::kBadImages;
      result.message = "camera " + std::to_string(c) + " (" + camera.source + "): " +
                       (alone.message.empty() ? alone.calibration.ceres.message : alone.message);
      return result;
    }
  }
  // Frames by the pairing's keys; each camera's views by their files.
  result.view_of_frame.assign(num_frames, std::vector<int>(num_cameras, -1));
  for (int c = 0; c < num_cameras; ++c) {
    const CalibrateResult& alone = result.cameras[c];
    for (size_t v = 0; v < alone.data.views.size(); ++v) {
      const std::string& file = alone.images->images[alone.used_index[v]].file;
      const auto& files = cameras[c].files_by_frame;
      const auto it = std::find(files.begin(), files.end(), file);
      if (it != files.end()) result.view_of_frame[it - files.begin()][c] = static_cast<int>(v);
    }
  }
  for (size_t f = 0; f < num_frames; ++f) {
    std::string name;
    for (const RigCameraImages& camera : cameras) {
      if (!camera.files_by_frame[f].empty()) {
        name = camera.files_by_frame[f];
        break;
      }
    }
    result.frame_names.push_back(name);
  }
  SolveRigFrom(options, &result);
  return result;
}

namespace {

void SolveRigFrom(const CalibrateRigOptions& options, CalibrateRigResult* result) {
  const int num_cameras = static_cast<int>(result->cameras.size());
  const size_t num_frames = result->view_of_frame.size();
  for (int c = 0; c < num_cameras; ++c) {
    if (!result->cameras[c].IsUsable()) {
      result->status = CalibrateRigResult::Status::kFailed;
      result->message =
          CameraName(*result, c) + ": calibrated alone: " +
          (result->cameras[c].message.empty() ? result->cameras[c].calibration.ceres.message
                                              : result->cameras[c].message);
      return;
    }
  }
  // The frames, the board poses each camera found, and the rig's cameras as calibrated alone.
  result->frames.assign(num_frames, RigFrame());
  std::vector<std::vector<Rigid3>> cam_from_board(num_cameras, std::vector<Rigid3>(num_frames));
  std::vector<std::vector<bool>> has_pose(num_cameras, std::vector<bool>(num_frames, false));
  for (size_t f = 0; f < num_frames; ++f) {
    RigFrame& frame = result->frames[f];
    frame.name = result->frame_names[f];
    frame.views_by_camera.resize(num_cameras);
    for (int c = 0; c < num_cameras; ++c) {
      const int v = result->view_of_frame[f][c];
      if (v < 0) continue;
      frame.views_by_camera[c] = result->cameras[c].data.views[v];
      cam_from_board[c][f] = result->cameras[c].calibration.ceres.cam_from_object[v];
      has_pose[c][f] = true;
    }
  }
  // Overlaps: the cameras each shares a frame with.
  result->overlaps.assign(num_cameras, {});
  for (int a = 0; a < num_cameras; ++a) {
    for (int b = 0; b < num_cameras; ++b) {
      if (a == b) continue;
      for (size_t f = 0; f < num_frames; ++f) {
        if (has_pose[a][f] && has_pose[b][f]) {
          result->overlaps[a].push_back(b);
          break;
        }
      }
    }
  }
  CameraRig rig = result->rig.rig;
  for (int c = 0; c < num_cameras; ++c) {
    const CalibrateResult& alone = result->cameras[c];
    RigCamera& camera = rig.cameras[c];
    camera.intrinsics = alone.calibration.camera.intrinsics;
    camera.lens_model = alone.model;
    camera.image_width = alone.data.image_width;
    camera.image_height = alone.data.image_height;
  }
  std::vector<Rigid3> rig_from_board;
  if (options.init) {
    for (int c = 0; c < num_cameras; ++c) {
      rig.cameras[c].cam_from_rig = options.init->cameras[c].cam_from_rig;
      rig.cameras[c].intrinsics = options.init->cameras[c].intrinsics;
      rig.cameras[c].lens_model = options.init->cameras[c].lens_model;
    }
    rig_from_board = FramePosesThroughRig(*result, rig);
  } else {
    result->init =
        InitRigExtrinsics(result->frames, cam_from_board, has_pose, &rig, &rig_from_board);
    if (!result->init.IsUsable()) {
      result->status = result->init.message.find("cut off") != std::string::npos
                           ? CalibrateRigResult::Status::kDisconnected
                           : CalibrateRigResult::Status::kFailed;
      result->message = result->init.message;
      return;
    }
  }
  RigRefineOptions refine;
  for (const RigCamera& camera : rig.cameras) refine.models.push_back(camera.lens_model);
  refine.estimate_skew = options.estimate_skew;
  refine.fix_intrinsics = options.evaluate_only;
  refine.fix_extrinsics = options.evaluate_only;
  refine.compute_covariance = !options.evaluate_only;
  result->rig = RefineRig(result->frames, rig, rig_from_board, refine);
  result->evaluated = options.evaluate_only;
  if (!result->rig.IsUsable()) {
    result->status = CalibrateRigResult::Status::kFailed;
    result->message = "the joint solve failed: " + result->rig.message;
    return;
  }
  const bool jackknife =
      !options.evaluate_only && (options.jackknife == CalibrateOptions::Jackknife::kOn ||
                                 (options.jackknife == CalibrateOptions::Jackknife::kAuto &&
                                  static_cast<int>(num_frames) <= kJackknifeAutoMaxViews));
  if (jackknife) {
    RigJackknifeOptions jack;
    jack.refine = refine;
    result->jackknife = JackknifeRig(result->frames, result->rig, jack);
  }
  for (int a = 0; a < num_cameras; ++a) {
    for (int b = a + 1; b < num_cameras; ++b) {
      EpipolarErrors errors = ComputeEpipolarErrors(result->frames, result->rig.rig, a, b);
      if (errors.num_points > 0) result->epipolar.push_back(std::move(errors));
    }
  }
  for (size_t f = 0; f < num_frames; ++f) {
    for (int c = 0; c < num_cameras; ++c) {
      const int v = result->view_of_frame[f][c];
      if (v < 0) continue;
      const double joint = result->rig.frame_rms_px[f][c];
      const double alone = result->cameras[c].calibration.ceres.view_rms_px[v];
      if (joint > kDisagreeFactor * alone && joint > alone + kDisagreeMinPx) {
        result->disagreements.push_back({static_cast<int>(f), c, joint, alone});
      }
    }
  }
  result->status = CalibrateRigResult::Status::kOk;
}

}  // namespace

std::string FormatRigReport(const CalibrateRigResult& result) {
  std::ostringstream out;
  if (result.cameras.empty() && !result.IsUsable()) {
    return "rig calibration refused: " + result.message + "\n";
  }
  char line[512];
  const int num_cameras = static_cast<int>(result.cameras.size());
  out << "rig of " << num_cameras << " cameras, " << result.frames.size() << " frames";
  if (result.evaluated) out << " (the given rig evaluated: intrinsics and extrinsics fixed)";
  out << "\n";
  for (int c = 0; c < num_cameras; ++c) {
    const CalibrateResult& alone = result.cameras[c];
    int frames_seen = 0;
    for (const std::vector<int>& row : result.view_of_frame) frames_seen += row[c] >= 0;
    std::snprintf(line, sizeof(line), "  camera %d  %-28s %-18s %2d frames  alone %.3f px", c,
                  CameraName(result, c).c_str(), alone.calibration.camera.ModelName().c_str(),
                  frames_seen, alone.calibration.ceres.rms_reproj_px);
    out << line;
    if (result.IsUsable()) {
      std::snprintf(line, sizeof(line), "  joint %.3f px", result.rig.camera_rms_px[c]);
      out << line;
    }
    out << "\n";
  }
  if (!result.IsUsable()) {
    out << "rig calibration failed: " << result.message << "\n";
    return out.str();
  }
  const CameraRig& rig = result.rig.rig;
  for (int c = 0; c < num_cameras; ++c) {
    const RigCamera& camera = rig.cameras[c];
    const IntrinsicsArray& stds = result.rig.intrinsics_std[c];
    const std::array<double, 10> params = camera.intrinsics.Params();
    const auto& names = ParamNames(camera.intrinsics.family);
    out << "camera " << c << " intrinsics (joint solve, +- 1 std):\n";
    for (int i = 0; i < 10; ++i) {
      if (std::string(names[i]) == "-") continue;
      const bool phi = i == 2;
      const double value = phi ? params[i] * 180.0 / M_PI : params[i];
      const double std = phi ? stds[i] * 180.0 / M_PI : stds[i];
      if (std::isnan(std) && phi) continue;  // phi fixed at 90 deg.
      std::snprintf(line, sizeof(line), "  %-8s %14.6f", phi ? "phi_deg" : names[i], value);
      out << line;
      if (!std::isnan(std)) {
        std::snprintf(line, sizeof(line), " +- %.6f", std);
        out << line;
      } else {
        out << " (fixed)";
      }
      out << "\n";
    }
    if (c < static_cast<int>(result.rig.projection.size()) && result.rig.projection[c].IsSet()) {
      const UncertaintyMap map = ProjectionUncertaintyMap(
          camera.intrinsics, result.rig.projection[c], camera.image_width, camera.image_height, {});
      std::snprintf(line, sizeof(line),
                    "  projection uncertainty (rays at infinity, formal, 1 sigma): centre %.3f px, "
                    "median %.3f px, worst %.3f px (%s)\n",
                    map.centre_px, map.median_px, map.max_px,
                    WorstRegion(map.worst_std_px, nullptr).c_str());
      out << line;
    }
  }
  const bool jack = result.jackknife && result.jackknife->IsUsable();
  for (int c = 1; c < num_cameras; ++c) {
    const RigPoseUncertainty& u = result.rig.pose_uncertainty[c];
    const Eigen::Vector3d r = rig.RelativeRotationDeg(c);
    const Eigen::Vector3d t = rig.cameras[c].cam_from_rig.translation * 1000.0;
    const Eigen::Vector3d centre = rig.CentreInRig(c) * 1000.0;
    out << "camera " << c << " from camera 0 (its cam_from_rig; the target's metres in mm)"
        << (result.evaluated ? ", fixed" : "") << ":\n";
    if (result.evaluated) {
      std::snprintf(line, sizeof(line),
                    "  baseline           %.3f mm\n"
                    "  rotation vector    x %.4f  y %.4f  z %.4f deg (angle %.4f deg)\n",
                    rig.BaselineM(c) * 1000.0, r.x(), r.y(), r.z(), r.norm());
    } else {
      std::snprintf(line, sizeof(line),
                    "  baseline           %.3f +- %.3f mm (direction +- %.4f deg)\n"
                    "  rotation vector    x %.4f +- %.4f  y %.4f +- %.4f  z %.4f +- %.4f deg "
                    "(angle %.4f deg)\n",
                    rig.BaselineM(c) * 1000.0, u.baseline_std_mm, u.baseline_direction_std_deg,
                    r.x(), u.rotation_std_deg.x(), r.y(), u.rotation_std_deg.y(), r.z(),
                    u.rotation_std_deg.z(), r.norm());
    }
    out << line;
    if (jack) {
      const RigPoseUncertainty& j = result.jackknife->pose[c];
      std::snprintf(line, sizeof(line),
                    "  jackknife std      baseline %.3f mm (direction %.4f deg), rotation x %.4f"
                    "  y %.4f  z %.4f deg\n",
                    j.baseline_std_mm, j.baseline_direction_std_deg, j.rotation_std_deg.x(),
                    j.rotation_std_deg.y(), j.rotation_std_deg.z());
      out << line;
    }
    if (c < static_cast<int>(result.rig.transfer.size()) && result.rig.transfer[c].IsSet()) {
      // The relative pose in pixels: camera 0's rays, and its points at 1 m, in camera c.
      const Rigid3 cam_c_from_cam_0 =
          rig.cameras[c].cam_from_rig * rig.cameras[0].cam_from_rig.Inverse();
      UncertaintyMapOptions near;
      near.distance_m = 1.0;
      const UncertaintyMap rays = TransferUncertaintyMap(
          rig.cameras[0], rig.cameras[c], cam_c_from_cam_0, result.rig.transfer[c], {});
      const UncertaintyMap at_1m = TransferUncertaintyMap(
          rig.cameras[0], rig.cameras[c], cam_c_from_cam_0, result.rig.transfer[c], near);
      if (std::isfinite(rays.median_px)) {
        std::snprintf(line, sizeof(line),
                      "  in camera %d's pixels: camera 0's rays land within %.3f px median "
                      "(worst %.3f), its points at 1 m within %.3f px (formal, 1 sigma)\n",
                      c, rays.median_px, rays.max_px, at_1m.median_px);
        out << line;
      }
    }
    std::snprintf(line, sizeof(line), "  translation        %.3f %.3f %.3f mm\n", t.x(), t.y(),
                  t.z());
    out << line;
    std::snprintf(line, sizeof(line), "  centre in rig      %.3f %.3f %.3f mm\n", centre.x(),
                  centre.y(), centre.z());
    out << line;
    if (!result.init.parent.empty() && result.init.parent[c] >= 0) {
      std::snprintf(line, sizeof(line), "  started from       camera %d (%d corners shared)\n",
                    result.init.parent[c], result.init.shared_points[c]);
      out << line;
    }
  }
  if (result.jackknife && !result.jackknife->IsUsable()) {
    out << "jackknife: not computed: " << result.jackknife->message << "\n";
  } else if (jack) {
    std::snprintf(line, sizeof(line),
                  "jackknife std: the spread of %d joint solves each leaving one frame out; "
                  "quote it where it exceeds the formal std\n",
                  result.jackknife->num_frames);
    out << line;
  }
  for (const EpipolarErrors& e : result.epipolar) {
    std::snprintf(line, sizeof(line), "epipolar error cameras %d-%d: %.3f px RMS over %d corners\n",
                  e.camera_a, e.camera_b, e.rms_px, e.num_points);
    out << line;
  }
  std::snprintf(line, sizeof(line), "joint RMS %.3f px over %d corners, sigma_hat %.3f px\n",
                result.rig.rms_reproj_px, result.rig.num_points, result.rig.sigma_hat_px);
  out << line;
  if (result.disagreements.empty()) {
    out << "frames that disagree with the rig: none\n";
  } else {
    out << "frames that disagree with the rig (joint RMS > " << kDisagreeFactor << "x and > "
        << kDisagreeMinPx << " px above the camera alone):\n";
    for (const RigFrameDisagreement& d : result.disagreements) {
      std::snprintf(line, sizeof(line), "  %-24s camera %d  joint %.3f px  alone %.3f px\n",
                    FrameName(result, d.frame).c_str(), d.camera, d.joint_rms_px, d.alone_rms_px);
      out << line;
    }
  }
  return out.str();
}

}  // namespace calibench
