// The Kalibr camchain of a rig (rig_io.h).
#include <yaml-cpp/yaml.h>

#include "io/camera_io_formats.h"
#include "io/rig_io_formats.h"

namespace calibench {
namespace rig_io_internal {

using camera_io_internal::Fail;

namespace {

// A 4 x 4 row list [[R t], [0 0 0 1]] at `at`: a proper rotation, the last row (0, 0, 0, 1).
bool ReadTransform(const YAML::Node& node, const std::string& at, Rigid3* pose, std::string* why) {
  if (!node) {
    return Fail(why, at + ": missing (from cam1 on, the pose of the camera from the previous one)");
  }
  const std::string shape = at + ": expected a 4 x 4 matrix (a list of 4 rows of 4 numbers)";
  if (!node.IsSequence() || node.size() != 4) return Fail(why, shape);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    const YAML::Node row = node[r];
    if (!row.IsSequence() || row.size() != 4) return Fail(why, shape);
    for (int c = 0; c < 4; ++c) {
      try {
        m(r, c) = row[c].as<double>();
      } catch (const YAML::Exception&) {
        return Fail(why, at + ": '" + row[c].Scalar() + "' is not a number");
      }
    }
  }
  if (!m.allFinite()) return Fail(why, at + ": non-finite entries");
  if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) {
    return Fail(why, at + ": the last row must be [0, 0, 0, 1]");
  }
  pose->rotation = m.topLeftCorner<3, 3>();
  pose->translation = m.topRightCorner<3, 1>();
  return CheckFileRotation(at, pose->rotation, why);
}

}  // namespace

bool WriteKalibrRig(const std::string& path, const RigFile& rig, std::string* why) {
  const int n = rig.rig.NumCameras();
  if (!rig.cam_overlaps.empty() && static_cast<int>(rig.cam_overlaps.size()) != n) {
    return Fail(why, path + ": cam_overlaps: " + std::to_string(rig.cam_overlaps.size()) +
                         " lists for " + std::to_string(n) + " cameras (one each, or none)");
  }
  if (!rig.rostopics.empty() && static_cast<int>(rig.rostopics.size()) != n) {
    return Fail(why, path + ": rostopic: " + std::to_string(rig.rostopics.size()) + " topics for " +
                         std::to_string(n) + " cameras (one each, or none)");
  }
  for (int c = 0; c < n; ++c) {
    const std::string cam = "cam" + std::to_string(c);
    if (!camera_io_internal::CheckKalibrCamera(path + ": " + cam, rig.rig.cameras[c].intrinsics,
                                               why)) {
      return false;
    }
    if (rig.cam_overlaps.empty()) continue;
    for (int other : rig.cam_overlaps[c]) {
      if (other < 0 || other >= n || other == c) {
        return Fail(why, path + ": " + cam + ".cam_overlaps: " + std::to_string(other) +
                             " is not another camera (0.." + std::to_string(n - 1) + ")");
      }
    }
  }
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  for (int c = 0; c < n; ++c) {
    out << YAML::Key << "cam" + std::to_string(c) << YAML::Value << YAML::BeginMap;
    if (c > 0) {
      const Rigid3 t = rig.rig.CamFromCam(c, c - 1);
      Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
      m.topLeftCorner<3, 3>() = t.rotation;
      m.topRightCorner<3, 1>() = t.translation;
      out << YAML::Key << "T_cn_cnm1" << YAML::Value << YAML::BeginSeq;
      for (int r = 0; r < 4; ++r) {
        out << YAML::Flow << YAML::BeginSeq;
        for (int k = 0; k < 4; ++k) out << m(r, k);
        out << YAML::EndSeq;
      }
      out << YAML::EndSeq;
    }
    camera_io_internal::EmitKalibrCamera(CameraFileOf(rig, c), &out);
    if (!rig.cam_overlaps.empty()) {
      out << YAML::Key << "cam_overlaps" << YAML::Value << YAML::Flow << rig.cam_overlaps[c];
    }
    if (!rig.rostopics.empty() && !rig.rostopics[c].empty()) {
      out << YAML::Key << "rostopic" << YAML::Value << rig.rostopics[c];
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return camera_io_internal::WriteText(path, std::string(out.c_str()) + "\n", why);
}

bool ReadKalibrRig(const std::string& path, const std::string& raw, RigFile* rig,
                   std::string* why) {
  YAML::Node root;
  try {
    root = YAML::Load(raw);
  } catch (const YAML::Exception& e) {
    return Fail(why, path + ": (yaml): " + e.what());
  }
  if (!root.IsMap() || !root["cam0"]) {
    return Fail(why, path + ": neither a Kalibr camchain (no cam0) nor an OpenCV stereo file");
  }
  bool any_overlaps = false, any_topic = false;
  for (int c = 0; root["cam" + std::to_string(c)]; ++c) {
    const std::string cam = "cam" + std::to_string(c);
    const YAML::Node node = root[cam];
    if (!node.IsMap()) return Fail(why, path + ": " + cam + ": expected a map");
    CameraFile camera;
    if (!camera_io_internal::ReadKalibrCamera(path, node, cam, &camera, why)) return false;
    Rigid3 cam_from_rig;
    if (c > 0) {
      Rigid3 cn_from_cnm1;
      if (!ReadTransform(node["T_cn_cnm1"], path + ": " + cam + ".T_cn_cnm1", &cn_from_cnm1, why)) {
        return false;
      }
      cam_from_rig = cn_from_cnm1 * rig->rig.cameras[c - 1].cam_from_rig;
    }
    AddCamera(camera, cam_from_rig, rig);
    std::vector<int> overlaps;
    if (const YAML::Node o = node["cam_overlaps"]) {
      try {
        overlaps = o.as<std::vector<int>>();
      } catch (const YAML::Exception&) {
        return Fail(why, path + ": " + cam + ".cam_overlaps: expected a list of camera indices");
      }
      any_overlaps = true;
    }
    rig->cam_overlaps.push_back(overlaps);
    std::string topic;
    if (const YAML::Node t = node["rostopic"]) {
      topic = t.as<std::string>("");
      any_topic = true;
    }
    rig->rostopics.push_back(topic);
  }
  if (!any_overlaps) rig->cam_overlaps.clear();
  if (!any_topic) rig->rostopics.clear();
  // Kalibr files hold no standard deviations.
  rig->intrinsics_std.clear();
  if (rig->rig.NumCameras() < 2) {
    return Fail(why, path + ": a rig needs cam0 and cam1 at least (found cam0 only)");
  }
  return true;
}

}  // namespace rig_io_internal
}  // namespace calibench
