#include <cmath>
#include <vector>

#include "io/camera_io_formats.h"

namespace calibench {
namespace camera_io_internal {
// Kalibr's camera_model names and intrinsics order for each family (Kalibr's
// kalibr_common/ConfigReader.py, AslamCamera): the lens parameters first, then fu fv pu pv.
struct KalibrModel {
  LensFamily family;
  const char* camera_model;
  std::vector<const char*> lens;  // The fields before fu fv pu pv.
};
const std::vector<KalibrModel>& KalibrModels() {
  static const std::vector<KalibrModel> models = {
      {LensFamily::kRadTan, "pinhole", {}},
      {LensFamily::kEquidistant, "pinhole", {}},
      {LensFamily::kUnified, "omni", {"xi"}},
      {LensFamily::kEucm, "eucm", {"alpha", "beta"}},
      {LensFamily::kDoubleSphere, "ds", {"xi", "alpha"}},
  };
  return models;
}

double& LensField(CameraIntrinsics* k, const std::string& name) {
  return name == "xi" ? k->xi : name == "alpha" ? k->alpha : k->beta;
}

// distortion_model and its coefficients for a family.
void KalibrDistortion(const CameraIntrinsics& k, std::string* model, std::vector<double>* coeffs) {
  switch (k.family) {
    case LensFamily::kRadTan:
    case LensFamily::kUnified:
      *model = "radtan";
      *coeffs = {k.k1, k.k2, k.p1, k.p2};
      return;
    case LensFamily::kEquidistant:
      *model = "equidistant";
      *coeffs = {k.k1, k.k2, k.k3, k.k4};
      return;
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere:
      *model = "none";
      coeffs->clear();
      return;
  }
}

const KalibrModel& KalibrModelOf(LensFamily family) {
  for (const KalibrModel& m : KalibrModels()) {
    if (m.family == family) return m;
  }
  return KalibrModels()[0];
}

bool WriteKalibr(const std::string& path, const CameraFile& camera, std::string* why) {
  CameraIntrinsics k = camera.intrinsics;
  if (HasSkew(k)) {
    return Fail(why, path + ": kalibr: Kalibr's cameras have no skew (phi_deg " +
                         Number(k.phi_deg) + "); calibrate without --skew or write opencv");
  }
  if (k.family == LensFamily::kRadTan && k.k3 != 0) {
    return Fail(why, path + ": kalibr: Kalibr's radtan model has k1 k2 r1 r2, no k3 (k3 " +
                         Number(k.k3) + "); use --model pinhole-radtan4 or write opencv/mrcal");
  }
  const KalibrModel& m = KalibrModelOf(k.family);
  std::string distortion;
  std::vector<double> coeffs;
  KalibrDistortion(k, &distortion, &coeffs);
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap << YAML::Key << "cam0" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "camera_model" << YAML::Value << m.camera_model;
  out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const char* field : m.lens) out << LensField(&k, field);
  out << k.fku_px << k.fkv_px << k.u0_px << k.v0_px << YAML::EndSeq;
  out << YAML::Key << "distortion_model" << YAML::Value << distortion;
  out << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (double c : coeffs) out << c;
  out << YAML::EndSeq;
  out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << camera.image_width << camera.image_height << YAML::EndSeq;
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
  const bool takes_radtan = name == "pinhole" || name == "omni";
  if (model == "radtan" && takes_radtan) {
    if (!KalibrNumbers(cam, at, "distortion_coeffs", 4, &d, why)) return false;
    k->k1 = d[0], k->k2 = d[1], k->p1 = d[2], k->p2 = d[3];
    return true;
  }
  if (model == "equidistant" && name == "pinhole") {
    if (!KalibrNumbers(cam, at, "distortion_coeffs", 4, &d, why)) return false;
    k->family = LensFamily::kEquidistant;
    k->k1 = d[0], k->k2 = d[1], k->k3 = d[2], k->k4 = d[3];
    return true;
  }
  return Fail(why, at + "distortion_model: '" + model + "' is not supported with camera_model " +
                       name + " (" +
                       (name == "pinhole" ? "radtan, equidistant, none"
                        : takes_radtan    ? "radtan, none"
                                          : "none") +
                       ")");
}

bool ReadKalibr(const std::string& path, const YAML::Node& root, CameraFile* camera,
                std::string* why) {
  const YAML::Node cam = root["cam0"];
  const std::string at = path + ": cam0.";
  const std::string name = cam["camera_model"] ? cam["camera_model"].as<std::string>("") : "";
  const KalibrModel* m = nullptr;
  for (const KalibrModel& candidate : KalibrModels()) {
    if (name == candidate.camera_model && m == nullptr) m = &candidate;
  }
  if (m == nullptr) {
    return Fail(why, at + "camera_model: '" + name +
                         "' is not a Kalibr camera model calibench reads (pinhole, omni, eucm, "
                         "ds)");
  }
  std::vector<double> intr, res;
  if (!KalibrNumbers(cam, at, "intrinsics", m->lens.size() + 4, &intr, why) ||
      !KalibrNumbers(cam, at, "resolution", 2, &res, why)) {
    return false;
  }
  CameraIntrinsics k;
  k.family = m->family;
  for (size_t i = 0; i < m->lens.size(); ++i) LensField(&k, m->lens[i]) = intr[i];
  const double* pinhole = intr.data() + m->lens.size();
  k.fku_px = pinhole[0], k.fkv_px = pinhole[1], k.u0_px = pinhole[2], k.v0_px = pinhole[3];
  if (!ReadKalibrDistortion(cam, at, *m, &k, why)) return false;
  std::string reason;
  if (!k.Check(&reason)) return Fail(why, at + "intrinsics: " + reason);
  SetCameraWithoutStd(k, res[0], res[1], camera);
  return true;
}

}  // namespace camera_io_internal
}  // namespace calibench
