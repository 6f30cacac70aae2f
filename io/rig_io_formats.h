// The rig file formats of rig_io.h, one source file each (rig_io_kalibr.cc, rig_io_opencv.cc,
// rig_io.cc: mrcal and the dispatch), and the helpers they share. Internal to io/: callers use
// rig_io.h.
#pragma once

#include <Eigen/Core>
#include <string>

#include "io/rig_io.h"

namespace calibench {
namespace rig_io_internal {

// The one-camera file of rig camera c (its std from rig.intrinsics_std, else NaN).
CameraFile CameraFileOf(const RigFile& rig, int c);
// A rig camera from a camera file read back (name "cam<c>"); its std into rig->intrinsics_std.
void AddCamera(const CameraFile& camera, const Rigid3& cam_from_rig, RigFile* rig);
// A rotation read from a file: orthonormal to 1e-6 and proper; else false with *why = `at` and
// the reason.
bool CheckFileRotation(const std::string& at, const Eigen::Matrix3d& r, std::string* why);

bool WriteKalibrRig(const std::string& path, const RigFile& rig, std::string* why);
bool ReadKalibrRig(const std::string& path, const std::string& raw, RigFile* rig, std::string* why);
bool WriteOpenCvRig(const std::string& path, const RigFile& rig, std::string* why);
bool ReadOpenCvRig(const std::string& path, RigFile* rig, std::string* why);

}  // namespace rig_io_internal
}  // namespace calibench
