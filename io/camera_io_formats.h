// The camera file formats of camera_io.h, one source file each (camera_io_opencv.cc,
// camera_io_kalibr.cc, camera_io_mrcal.cc), and the helpers they share (camera_io.cc). Internal to
// io/: callers use camera_io.h.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>

#include "io/camera_io.h"

namespace cv {
class FileStorage;
}

namespace calibench {
namespace camera_io_internal {

constexpr double kRadToDeg = 180.0 / M_PI;

// *why = message; false.
bool Fail(std::string* why, const std::string& message);
// phi differs from 90 deg beyond what a fit without skew leaves.
bool HasSkew(const CameraIntrinsics& k);
// A double written with 17 significant digits.
std::string Number(double value);
// A temporary beside `path` with the same extension (cv::FileStorage picks YAML/XML/JSON by it),
// and its rename onto `path` (removed on failure): the files are written atomically.
std::string TemporaryBeside(const std::string& path);
bool RenameInto(const std::string& tmp, const std::string& path, std::string* why);
// `text` into `path` through a temporary.
bool WriteText(const std::string& path, const std::string& text, std::string* why);
// lens_model (the smallest model of the family holding every non-zero coefficient) and
// estimate_skew from the intrinsics.
void InferModel(CameraFile* camera);
// A camera read from a format that holds no standard deviations (kalibr, mrcal): its intrinsics
// and image size, every std NaN, the model inferred.
void SetCameraWithoutStd(const CameraIntrinsics& k, double width, double height,
                         CameraFile* camera);
// std_<name> of raw slot i in the family's order (ParamNames: std_k1, std_xi, std_alpha, ..);
// empty for an unused slot.
std::string StdName(LensFamily family, int i);

bool WriteOpenCv(const std::string& path, const CameraFile& camera, std::string* why);
// The name of a field of one camera in an OpenCV file: the one-camera file's own (SameName), or
// a stereo file's (M1, D1, distortion_model_1, ..; rig_io_opencv.cc).
using OpenCvFieldName = std::function<std::string(const std::string&)>;
std::string SameName(const std::string& field);
// One camera's fields into an open storage (WriteOpenCv's; with_fit: rms_reproj_px and
// view_rms_px too), and back (ReadOpenCv's; errors name path and the field).
void WriteOpenCvCamera(const CameraFile& camera, bool with_fit, const OpenCvFieldName& name,
                       cv::FileStorage* out);
bool ReadOpenCvCamera(const std::string& path, const cv::FileStorage& in,
                      const OpenCvFieldName& name, CameraFile* camera, std::string* why);
// `yaml_text`: the file's YAML when it lacks OpenCV's "%YAML:1.0" first line (read from memory).
bool ReadOpenCv(const std::string& path, CameraFile* camera, std::string* why,
                const std::string& yaml_text = "");
bool WriteKalibr(const std::string& path, const CameraFile& camera, std::string* why);
// Whether Kalibr can hold the camera (no skew, no k3, a family with a camera_model); the reason
// after `at` ("file: kalibr: ..").
bool CheckKalibrCamera(const std::string& at, const CameraIntrinsics& k, std::string* why);
// camera_model .. resolution of one camera into the open map of a camN (CheckKalibrCamera first).
void EmitKalibrCamera(const CameraFile& camera, YAML::Emitter* out);
// One camera's fields from the map `cam` (named cam_name in errors: "file: cam1.intrinsics: ..").
bool ReadKalibrCamera(const std::string& path, const YAML::Node& cam, const std::string& cam_name,
                      CameraFile* camera, std::string* why);
// `root`: the file's YAML, a map with cam0.
bool ReadKalibr(const std::string& path, const YAML::Node& root, CameraFile* camera,
                std::string* why);
bool WriteMrcal(const std::string& path, const CameraFile& camera, std::string* why);
// WriteMrcal with the extrinsics rt_cam_ref (r Rodrigues, t; nullptr: the identity, written as
// [ 0, 0, 0, 0, 0, 0 ]) and the first comment line (after "# ").
bool WriteMrcalCamera(const std::string& path, const CameraFile& camera, const double* rt_cam_ref,
                      const std::string& comment, std::string* why);
// The extrinsics rt_cam_ref of a .cameramodel's text; false (and *why) when missing or not 6
// numbers.
bool ReadMrcalExtrinsics(const std::string& path, const std::string& raw, double rt_cam_ref[6],
                         std::string* why);
// `raw`: the file's text.
bool ReadMrcal(const std::string& path, const std::string& raw, CameraFile* camera,
               std::string* why);

}  // namespace camera_io_internal
}  // namespace calibench
