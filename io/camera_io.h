// Camera files: what `calibrate` writes (--out, --format) and reads back (--init), in
// the formats of the tools calibration results are handed to. One home for all three.
//
//   opencv  cv::FileStorage YAML/XML/JSON (by extension), readable by any OpenCV program:
//           camera_matrix (A of camera/camera.h, with its skew term a2 = -fku cot(phi)),
//           distortion_model (radtan | equidistant | unified | eucm | double-sphere), the lens:
//             radtan       distortion_coefficients k1 k2 p1 p2 k3 (cv::calibrateCamera's order);
//             equidistant  distortion_coefficients k1 k2 k3 k4 (cv::fisheye's);
//             unified      distortion_coefficients k1 k2 p1 p2 and xi: cv::omnidir's K, D, xi, as
//                          its omni_calibration sample writes them (a file of that sample, with no
//                          distortion_model, reads as unified from its xi);
//             eucm         alpha, beta;   double-sphere  xi, alpha (no OpenCV counterpart: a
//                          reader must go by distortion_model, as for equidistant);
//           image_width, image_height; then calibench's own fields: model, fku_px, fkv_px,
//           phi_deg (exact, preferred on reading), rms_reproj_px, std_<parameter> (1 sigma, the
//           names of ParamNames: std_xi, std_alpha, ..), view_rms_px, and the projection
//           uncertainty (batch/projection_uncertainty.h) when known: projection_covariance
//           (Cov(z), 16 x 16), projection_sigma_px, projection_views, projection_scale (the
//           jackknife's factor already in it: calib/calibration_uncertainty.h).
//   kalibr  a camchain YAML (as kalibr_calibrate_cameras writes it) with one camera, cam0, in
//           Kalibr's orders (kalibr_common/ConfigReader.py):
//             camera_model pinhole  intrinsics [fu, fv, pu, pv], distortion_model radtan
//                                   ([k1, k2, r1, r2]), equidistant ([k1, k2, k3, k4]) or none;
//             camera_model omni     [xi, fu, fv, pu, pv], radtan or none      (unified);
//             camera_model eucm     [alpha, beta, fu, fv, pu, pv], none        (eucm);
//             camera_model ds       [xi, alpha, fu, fv, pu, pv], none          (double-sphere);
//           distortion_coeffs, resolution [w, h]. Kalibr's cameras have no skew and its radtan no
//           k3: such cameras are refused; so is any other camera_model.
//   mrcal   a .cameramodel (the Python-literal dict mrcal.cameramodel() reads): lensmodel,
//           intrinsics [fx, fy, cx, cy, distortion...], imagersize [w, h], extrinsics
//           (rt_cam_ref, identity). Radtan maps exactly to LENSMODEL_PINHOLE (no distortion),
//           LENSMODEL_OPENCV4 (k3 = 0) or LENSMODEL_OPENCV5; reading also takes LENSMODEL_OPENCV8
//           with k4 = k5 = k6 = 0. mrcal (2.2, Debian 12) has no skew and none of the other
//           families (Kannala-Brandt, unified, eucm, double sphere): such cameras are refused,
//           naming the reason.
// Reading checks every field's range (CameraIntrinsics::Check: xi >= 0 for unified, > -1 for the
// double sphere, alpha in [0, 1], beta > 0) and the number of coefficients a family has.
// Pixel convention: all three put the centre of pixel (i, j) at (i, j), as calibench does; the
// intrinsics are written unchanged. Numbers are written with 17 significant digits (an exact
// double round trip). Files are written atomically (a temporary beside them, then rename).
// Errors name the file, the field and the reason.
#pragma once

#include <string>

#include "calib/camera_file.h"

namespace calibench {

enum class CameraFormat { kOpenCv, kKalibr, kMrcal };
const char* ToString(CameraFormat format);
// "opencv", "kalibr", "mrcal"; false (and *why) for another name.
bool ParseCameraFormat(const std::string& name, CameraFormat* format, std::string* why);
// From the file name: *.cameramodel -> mrcal; *camchain*.yaml / *.kalibr.yaml -> kalibr; else
// opencv.
CameraFormat CameraFormatFromPath(const std::string& path);

bool WriteCameraFile(const std::string& path, CameraFormat format, const CameraFile& camera,
                     std::string* why);
// Reads any of the three, recognised from the content (mrcal: a dict with 'lensmodel'; kalibr:
// a cam0 map; opencv: camera_matrix). The lens model is the file's (opencv: its `model` field when
// present; otherwise the smallest of LensModels() holding every non-zero coefficient).
bool ReadCameraFile(const std::string& path, CameraFile* camera, std::string* why);

}  // namespace calibench
