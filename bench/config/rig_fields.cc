// The scenario format of a rig's camera (`rig.cameras[c]`), declared once as scenario_fields.cc
// declares the rest: its name, intrinsics, image size and cam_from_rig.
#include <Eigen/Core>
#include <string>

#include "bench/config/scenario.h"

namespace calibench {
namespace {

void VisitCamFromRig(FieldVisitor& v, RigCameraConfig& c) {
  v.Field({"rpy_deg", "deg",
           "Its rotation as roll, pitch, yaw (camera/pose.h FromRollPitchYawDeg: about the rig "
           "frame's x, y, z, i.e. camera 0's pitch, yaw and roll axes); or give R.",
           "", nullptr, c.rotation_as_matrix ? kNotWritten | kNotCompared : kNotCompared},
          &c.rpy_deg);
  v.Field({"R", "", "Its rotation as a 3x3 list of rows (a proper rotation).", "", nullptr,
           c.rotation_as_matrix || v.Reads() ? 0u : kNotWritten},
          &c.r);
  v.Exclusive("rpy_deg", {"R"}, "give the rotation once: rpy_deg or R");
  v.Field({"t_m", "m",
           "Its translation: camera 0's centre in this camera's frame (its norm is the "
           "baseline)."},
          &c.t_m);
  if (v.Reads()) {
    v.Check(nullptr, [&c](std::string* why) {
      c.rotation_as_matrix = c.r != Eigen::Matrix3d::Identity();
      if (!c.rotation_as_matrix) c.r = FromRollPitchYawDeg(c.rpy_deg);
      if (!c.rpy_deg.allFinite() || !c.t_m.allFinite() || !c.r.allFinite()) {
        return *why = "must be finite", false;
      }
      if (c.r.determinant() < 0) {
        return *why =
                   "the rotation is improper (det < 0, a reflection): a rig camera's must be a "
                   "rotation",
               false;
      }
      return CheckRotation(c.r, 1e-6, false, why);
    });
  }
}

}  // namespace

void Visit(FieldVisitor& v, RigCameraConfig& c) {
  v.Field({"name", "", "For messages (default: cam<c>).", "", nullptr, kOmitUnset}, &c.name);
  SectionOps intrinsics;
  intrinsics.visit = [&c](FieldVisitor& w) { Visit(w, c.intrinsics); };
  intrinsics.reset = [&c] { c.intrinsics_given = true; };
  intrinsics.flow = true;
  intrinsics.written = c.intrinsics_given;
  v.Section({"intrinsics", "",
             "Its intrinsics, as truth.intrinsics (any lens family); required but for camera 0 "
             "(whose are truth.intrinsics)."},
            intrinsics);
  v.Field({"image_size", "px", "[width, height]; default: the scenario's image_size.", "", nullptr,
           kOmitUnset},
          &c.image_width, &c.image_height);
  v.Check("image_size", [&c](std::string* why) {
    if (c.image_width == 0 && c.image_height == 0) return true;
    if (c.image_width < 1 || c.image_height < 1 || c.image_width > kMaxImageSide ||
        c.image_height > kMaxImageSide ||
        static_cast<double>(c.image_width) * c.image_height > kMaxImagePixels) {
      return *why = "must be two positive sizes within the scenario's bounds (or absent)", false;
    }
    return true;
  });
  SectionOps pose;
  pose.visit = [&c](FieldVisitor& w) { VisitCamFromRig(w, c); };
  pose.flow = true;
  v.Section({"cam_from_rig", "",
             "Its extrinsic (camera/rig.h): point_in_cam = cam_from_rig * point_in_rig, the rig "
             "frame being camera 0's; {rpy_deg or R, t_m}. Camera 0's is the identity."},
            pose);
}

}  // namespace calibench
