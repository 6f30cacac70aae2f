#include "camera/rig.h"

#include <sstream>

namespace calibench {

Rigid3 CameraRig::CamFromCam(int i, int j) const {
  return cameras[i].cam_from_rig * cameras[j].cam_from_rig.Inverse();
}

Eigen::Vector3d CameraRig::CentreInRig(int c) const {
  return cameras[c].cam_from_rig.Inverse().translation;
}

double CameraRig::BaselineM(int c) const { return cameras[c].cam_from_rig.translation.norm(); }

Eigen::Vector3d CameraRig::RelativeRotationDeg(int c) const {
  return LogSO3(cameras[c].cam_from_rig.rotation) * (180.0 / M_PI);
}

bool CameraRig::Check(std::string* why) const {
  const auto fail = [&](int c, const std::string& field, const std::string& reason) {
    if (why != nullptr) {
      const std::string name =
          cameras[c].name.empty() ? "camera " + std::to_string(c) : cameras[c].name;
      *why = name + ": " + field + ": " + reason;
    }
    return false;
  };
  if (cameras.size() < 2) {
    if (why != nullptr) {
      *why = "a rig needs at least 2 cameras, got " + std::to_string(cameras.size());
    }
    return false;
  }
  for (int c = 0; c < NumCameras(); ++c) {
    const RigCamera& camera = cameras[c];
    std::string reason;
    if (!camera.intrinsics.Check(&reason)) return fail(c, "intrinsics", reason);
    if (FamilyOf(camera.lens_model) != camera.intrinsics.family) {
      return fail(c, "lens_model",
                  std::string(ToString(camera.lens_model)) + " is not of the intrinsics' family " +
                      ToString(camera.intrinsics.family));
    }
    if (camera.image_width < 0 || camera.image_height < 0 ||
        (camera.image_width == 0) != (camera.image_height == 0)) {
      std::ostringstream msg;
      msg << camera.image_width << " x " << camera.image_height
          << ": both positive, or both 0 (unknown)";
      return fail(c, "image size", msg.str());
    }
    const Rigid3& pose = camera.cam_from_rig;
    if (!pose.translation.allFinite()) return fail(c, "cam_from_rig", "non-finite translation");
    if (!CheckRotation(pose.rotation, 1e-6, /*allow_improper=*/false, &reason)) {
      return fail(c, "cam_from_rig", reason);
    }
    if (c == 0) {
      const double rotation_off =
          (pose.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
      if (rotation_off > 1e-9 || pose.translation.norm() > 1e-9) {
        return fail(c, "cam_from_rig",
                    "camera 0 defines the rig frame: its cam_from_rig must be the identity");
      }
    } else if (BaselineM(c) <= 1e-9) {
      return fail(c, "cam_from_rig", "its centre coincides with camera 0's (baseline 0)");
    }
  }
  return true;
}

}  // namespace calibench
