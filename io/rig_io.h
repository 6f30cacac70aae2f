// Rig files: a camera rig (camera/rig.h) written and read in the formats of the tools users hand
// rig calibrations to. Conventions as camera/rig.h states them (rig frame = camera 0's, metres).
// The format is chosen from the path as CameraFormatFromPath (io/camera_io.h) does.
//
//   kalibr  a camchain YAML (as kalibr_calibrate_cameras writes it): cam0 .. camN-1, each with
//           the one-camera writer's camera_model, intrinsics, distortion_model, distortion_coeffs,
//           resolution (camera_io.h: what Kalibr cannot hold is refused, naming the camera), and
//           from cam1 on T_cn_cnm1 = CamFromCam(n, n - 1) (p_cam_n = T p_cam_n-1), a 4 x 4 row
//           list; cam_overlaps (the cameras each shares frames with) and rostopic when given.
//           Reading chains them: cam_from_rig_n = T_cn_cnm1 * cam_from_rig_n-1.
//   opencv  one cv::FileStorage file (YAML/XML/JSON by extension) for a 2-camera rig, in the names
//           of OpenCV's stereo_calib.cpp sample: M1 D1 M2 D2 (camera_matrix and
//           distortion_coefficients of the one-camera writer), R T (p_cam2 = R p_cam1 + T, i.e.
//           cam_from_rig of camera 2), E = [T]x R, F = M2^-T E M1^-1 (x2^T F x1 = 0 for the
//           pinhole pixels M (X/Z, Y/Z, 1) of a point's undistorted rays), and the rectification
//           R1 R2 P1 P2 Q: cv::stereoRectify (radtan, alpha -1, CALIB_ZERO_DISPARITY),
//           cv::fisheye::stereoRectify (equidistant, CALIB_ZERO_DISPARITY), otherwise — a mixed
//           pair or the omnidirectional families — calib/rectify.h's own; image size: camera 1's
//           (no rectification is written when it is unknown). The rest of each camera in the
//           one-camera writer's names with the suffix _1 / _2 (distortion_model_1, xi_1, model_1,
//           fku_px_1, fkv_px_1, phi_deg_1, image_width_1, image_height_1, std_<name>_1), and
//           rectification (opencv | opencv-fisheye | calibench). Reading takes M1 D1 M2 D2 R T
//           (and the _1 / _2 fields when present); E F R1 R2 P1 P2 Q are not read.
//   mrcal   one .cameramodel per camera (the one-camera writer's) with its extrinsics rt_cam_ref
//           = (Rodrigues r, t) of cam_from_rig: for the path base.cameramodel, the files
//           base-camera-0.cameramodel, base-camera-1.cameramodel, .. (MrcalRigPaths). mrcal 2.2's
//           families only (radtan without skew). Reading takes base-camera-0.. until one is
//           missing (given base.cameramodel or any one of the files); the reference of the files
//           need not be camera 0 (cam_from_rig_c = cam_c_from_ref * cam_0_from_ref^-1).
// Each camera's name reads back as "cam<i>" (the names are not stored); its lens model as the
// one-camera reader gives it (opencv: model_<i>; kalibr, mrcal: the smallest of the family's
// holding its coefficients). Numbers have 17 significant digits: intrinsics and (2 cameras) R, T
// round-trip exactly; chained or Rodrigues poses to ~1e-15. Writes are atomic (each file through
// a temporary beside it). Errors name the file, the field and the reason.
#pragma once

#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/rig.h"
#include "io/camera_io.h"

namespace calibench {

struct RigFile {
  CameraRig rig;
  // Optional: empty, or one per camera, each camera's 1-sigma intrinsics in CameraFile's layout
  // (NaN: unknown). Only the opencv format holds them (std_<name>_<i>).
  std::vector<IntrinsicsArray> intrinsics_std;
  // Optional (kalibr): empty, or per camera the other cameras it shares frames with.
  std::vector<std::vector<int>> cam_overlaps;
  // Optional (kalibr): empty, or per camera its ROS image topic.
  std::vector<std::string> rostopics;
};

// The mrcal files of a rig written to `path` (base.cameramodel -> base-camera-<c>.cameramodel).
std::vector<std::string> MrcalRigPaths(const std::string& path, int num_cameras);

// Writes the rig (CameraRig::Check first) in `format` (header comment). The opencv format takes
// exactly 2 cameras.
bool WriteRigFile(const std::string& path, CameraFormat format, const RigFile& rig,
                  std::string* why);
// Reads a rig written in any of the three formats: mrcal by the path (base.cameramodel), the
// others recognised from the content (kalibr: a cam0 map; opencv: M1). The result passes
// CameraRig::Check (else an error naming the camera).
bool ReadRigFile(const std::string& path, RigFile* rig, std::string* why);

}  // namespace calibench
