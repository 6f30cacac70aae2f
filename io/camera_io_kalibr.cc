#include <cmath>
#include <vector>

#include "io/camera_io_formats.h"

namespace calibench {
namespace camera_io_internal {
// Kalibr's camera_model names and intrinsics order for each family (Kalibr's
// kalibr_common/ConfigReader.py, AslamCamera; LensFamilyInfo::kalibr): the lens parameters first,
// then fu fv pu pv.
struct KalibrModel {
  LensFamily family;
  const char* camera_model;
  std::vector<const char*> lens;  // The fields before fu fv pu pv.
};
const std::vector<KalibrModel>& KalibrModels() {
  static const std::vector<KalibrModel> models = [] {
    std::vector<KalibrModel> rows;
    for (const LensFamilyInfo& info : LensFamilies()) {
      if (info.kalibr.camera_model == nullptr) continue;  // Kalibr cannot store it.
      KalibrModel row{info.family, info.kalibr.camera_model, {}};
      for (const char* field : info.kalibr.lens) {
        if (field != nullptr) row.lens.push_back(field);
      }
      rows.push_back(row);
    }
    return rows;
  }();
  return models;
}

// The lens fields Kalibr's distortion_coeffs hold for k's family, in Kalibr's order.
std::vector<const char*> KalibrCoefficientNames(LensFamily family) {
  std::vector<const char*> names;
  for (const char* name : InfoOf(family).kalibr.coefficients) {
    if (name != nullptr) names.push_back(name);
  }
  return names;
}

// distortion_model and its coefficients for a family.
void KalibrDistortion(const CameraIntrinsics& k, std::string* model, std::vector<double>* coeffs) {
  *model = InfoOf(k.family).kalibr.distortion_model;
  coeffs->clear();
  for (const char* name : KalibrCoefficientNames(k.family)) coeffs->push_back(*LensField(k, name));
}

// nullptr for a family Kalibr has no camera_model for.
const KalibrModel* KalibrModelOf(LensFamily family) {
  for (const KalibrModel& m : KalibrModels()) {
    if (m.family == family) return &m;
  }
  return nullptr;
}

bool CheckKalibrCamera(const std::string& path, const CameraIntrinsics& k, std::string* why) {
  if (HasSkew(k)) {
    return Fail(why, path + ": kalibr: Kalibr's cameras have no skew (phi_deg " +
                         Number(k.phi_deg) + "); calibrate without --skew or write opencv");
  }
  if (k.family == LensFamily::kRadTan && k.k3 != 0) {
    return Fail(why, path + ": kalibr: Kalibr's radtan model has k1 k2 r1 r2, no k3 (k3 " +
                         Number(k.k3) + "); use --model pinhole-radtan4 or write opencv/mrcal");
  }
  if (KalibrModelOf(k.family) == nullptr) {
    return Fail(why, path + ": kalibr: Kalibr has no camera model for the " +
                         std::string(InfoOf(k.family).known_as) + " lens; write opencv");
  }
  return true;
}

void EmitKalibrCamera(const CameraFile& camera, YAML::Emitter* out_emitter) {
  YAML::Emitter& out = *out_emitter;
  const CameraIntrinsics& k = camera.intrinsics;
  const KalibrModel& m = *KalibrModelOf(k.family);
  std::string distortion;
  std::vector<double> coeffs;
  KalibrDistortion(k, &distortion, &coeffs);
  out << YAML::Key << "camera_model" << YAML::Value << m.camera_model;
  out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const char* field : m.lens) out << *LensField(k, field);
  out << k.fku_px << k.fkv_px << k.u0_px << k.v0_px << YAML::EndSeq;
  out << YAML::Key << "distortion_model" << YAML::Value << distortion;
  out << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (double c : coeffs) out << c;
  out << YAML::EndSeq;
  out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << camera.image_width << camera.image_height << YAML::EndSeq;
}

bool WriteKalibr(const std::string& path, const CameraFile& camera, std::string* why) {
  if (!CheckKalibrCamera(path, camera.intrinsics, why)) return false;
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap << YAML::Key << "cam0" << YAML::Value << YAML::BeginMap;
  EmitKalibrCamera(camera, &out);
  out << YAML::EndMap << YAML::EndMap;
  return WriteText(path, std::string(out.c_str()) + "\n", why);
}

// A list of exactly `count` numbers at cam0.<field> (a missing list reads as empty).
bool KalibrNumbers(const YAML::Node& cam, const std::string& at, const char* field, size_t count,
                   std::vector<double>* values, std::string* why) {
  const YAML::Node node = cam[field];
  values->clear();
  if (!node && count == 0) return true;
  if (!node || !node.IsSequence() || node.size() != count) {
    return Fail(why, at + field + ": expected a list of " + std::to_string(count) + " numbers");
  }
  for (const YAML::Node& v : node) {
    try {
      values->push_back(v.as<double>());
    } catch (const YAML::Exception&) {
      return Fail(why, at + field + ": '" + v.Scalar() + "' is not a number");
    }
  }
  return true;
}

// distortion_model and distortion_coeffs for camera_model `m` into *k.
bool ReadKalibrDistortion(const YAML::Node& cam, const std::string& at, const KalibrModel& m,
                          CameraIntrinsics* k, std::string* why) {
  const std::string model =
      cam["distortion_model"] ? cam["distortion_model"].as<std::string>("") : "none";
  const std::string name = m.camera_model;
  std::vector<double> d;
  if (model == "none") return KalibrNumbers(cam, at, "distortion_coeffs", 0, &d, why);
  // The family of this camera_model whose distortion_model it is (pinhole + equidistant: the
  // equidistant family).
  std::string supported;
  for (const KalibrModel& row : KalibrModels()) {
    const char* distortion = InfoOf(row.family).kalibr.distortion_model;
    if (name != row.camera_model || std::string(distortion) == "none") continue;
    supported += std::string(distortion) + ", ";
    if (model != distortion) continue;
    const std::vector<const char*> fields = KalibrCoefficientNames(row.family);
    if (!KalibrNumbers(cam, at, "distortion_coeffs", fields.size(), &d, why)) return false;
    k->family = row.family;
    for (size_t i = 0; i < fields.size(); ++i) *LensField(k, fields[i]) = d[i];
    return true;
  }
  return Fail(why, at + "distortion_model: '" + model + "' is not supported with camera_model " +
                       name + " (" + supported + "none)");
}

bool ReadKalibrCamera(const std::string& path, const YAML::Node& cam, const std::string& cam_name,
                      CameraFile* camera, std::string* why) {
  const std::string at = path + ": " + cam_name + ".";
  const std::string name = cam["camera_model"] ? cam["camera_model"].as<std::string>("") : "";
  const KalibrModel* m = nullptr;
  for (const KalibrModel& candidate : KalibrModels()) {
    if (name == candidate.camera_model && m == nullptr) m = &candidate;
  }
  if (m == nullptr) {
    std::string names;  // pinhole, omni, eucm, ds.
    for (const KalibrModel& candidate : KalibrModels()) {
      if (names.find(candidate.camera_model) == std::string::npos) {
        names += (names.empty() ? "" : ", ") + std::string(candidate.camera_model);
      }
    }
    return Fail(why, at + "camera_model: '" + name +
                         "' is not a Kalibr camera model calibench reads (" + names + ")");
  }
  std::vector<double> intr, res;
  if (!KalibrNumbers(cam, at, "intrinsics", m->lens.size() + 4, &intr, why) ||
      !KalibrNumbers(cam, at, "resolution", 2, &res, why)) {
    return false;
  }
  CameraIntrinsics k;
  k.family = m->family;
  for (size_t i = 0; i < m->lens.size(); ++i) *LensField(&k, m->lens[i]) = intr[i];
  const double* pinhole = intr.data() + m->lens.size();
  k.fku_px = pinhole[0], k.fkv_px = pinhole[1], k.u0_px = pinhole[2], k.v0_px = pinhole[3];
  if (!ReadKalibrDistortion(cam, at, *m, &k, why)) return false;
  std::string reason;
  if (!k.Check(&reason)) return Fail(why, at + "intrinsics: " + reason);
  SetCameraWithoutStd(k, res[0], res[1], camera);
  return true;
}

bool ReadKalibr(const std::string& path, const YAML::Node& root, CameraFile* camera,
                std::string* why) {
  return ReadKalibrCamera(path, root["cam0"], "cam0", camera, why);
}

}  // namespace camera_io_internal
}  // namespace calibench
