#include "bench/config/camera_io.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

namespace calibench {
namespace {

namespace fs = std::filesystem;

constexpr double kRadToDeg = 180.0 / M_PI;
// A camera estimated without skew has phi = 90 deg to the last bit; anything beyond this is skew.
constexpr double kNoSkewTolDeg = 1e-9;

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

bool HasSkew(const CameraIntrinsics& k) { return std::abs(k.phi_deg - 90.0) > kNoSkewTolDeg; }

std::string Number(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

// A temporary beside `path` with the same extension (cv::FileStorage picks YAML/XML/JSON by it).
std::string TemporaryBeside(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / ("." + p.stem().string() + ".tmp" + p.extension().string())).string();
}

bool RenameInto(const std::string& tmp, const std::string& path, std::string* why) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (!ec) return true;
  fs::remove(tmp, ec);
  return Fail(why, path + ": rename failed: " + ec.message());
}

bool WriteText(const std::string& path, const std::string& text, std::string* why) {
  const std::string tmp = TemporaryBeside(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      return Fail(why, path + ": cannot write");
    }
  }
  return RenameInto(tmp, path, why);
}

// The smallest lens model of the family holding every non-zero coefficient.
LensModel InferLensModel(const CameraIntrinsics& k) {
  if (k.family != LensFamily::kRadTan) return FullModelOf(k.family);
  if (k.k3 != 0) return LensModel::kPinholeRadTan5;
  if (k.p1 != 0 || k.p2 != 0) return LensModel::kPinholeRadTan4;
  if (k.k1 != 0 || k.k2 != 0) return LensModel::kPinholeK2;
  return LensModel::kPinhole;
}

void InferModel(CameraFile* camera) {
  camera->lens_model = InferLensModel(camera->intrinsics);
  camera->estimate_skew = HasSkew(camera->intrinsics);
}

// ---- opencv ---------------------------------------------------------------------------------

// std_<name> of raw slot i in the family's order (ParamNames: std_k1, std_xi, std_alpha, ..);
// empty for an unused slot.
std::string StdName(LensFamily family, int i) {
  const std::string name = ParamNames(family)[i];
  return name == "-" ? "" : "std_" + name;
}

// The lens fields: radtan and equidistant as distortion_coefficients (cv::calibrateCamera's and
// cv::fisheye's); unified as cv::omnidir's (distortion_coefficients k1 k2 p1 p2 and a scalar xi,
// the fields its omni_calibration sample writes); eucm and the double sphere as their own scalars.
void WriteOpenCvLens(const CameraIntrinsics& k, cv::FileStorage* out) {
  switch (k.family) {
    case LensFamily::kRadTan:
      *out << "distortion_coefficients" << (cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3);
      return;
    case LensFamily::kEquidistant:
      *out << "distortion_coefficients" << (cv::Mat_<double>(1, 4) << k.k1, k.k2, k.k3, k.k4);
      return;
    case LensFamily::kUnified:
      *out << "distortion_coefficients" << (cv::Mat_<double>(1, 4) << k.k1, k.k2, k.p1, k.p2);
      *out << "xi" << k.xi;
      return;
    case LensFamily::kEucm:
      *out << "alpha" << k.alpha << "beta" << k.beta;
      return;
    case LensFamily::kDoubleSphere:
      *out << "xi" << k.xi << "alpha" << k.alpha;
      return;
  }
}

bool WriteOpenCv(const std::string& path, const CameraFile& camera, std::string* why) {
  const std::string tmp = TemporaryBeside(path);
  try {
    cv::FileStorage out(tmp, cv::FileStorage::WRITE);
    if (!out.isOpened()) return Fail(why, path + ": cannot open for writing");
    const CameraIntrinsics& k = camera.intrinsics;
    const Eigen::Matrix3d a = k.Matrix();
    cv::Mat camera_matrix(3, 3, CV_64F);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) camera_matrix.at<double>(r, c) = a(r, c);
    }
    out << "model" << camera.ModelName();
    out << "image_width" << camera.image_width << "image_height" << camera.image_height;
    out << "camera_matrix" << camera_matrix;
    out << "distortion_model" << ToString(k.family);
    WriteOpenCvLens(k, &out);
    out << "fku_px" << k.fku_px << "fkv_px" << k.fkv_px << "phi_deg" << k.phi_deg;
    out << "rms_reproj_px" << camera.rms_reproj_px;
    for (int i = 0; i < 10; ++i) {
      const double s = camera.intrinsics_std[i];
      const std::string name = StdName(k.family, i);
      if (std::isfinite(s) && !name.empty()) out << name << (i == 2 ? s * kRadToDeg : s);
    }
    out << "view_rms_px" << camera.view_rms_px;
    out.release();
  } catch (const cv::Exception& e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    return Fail(why, path + ": " + e.what());
  }
  return RenameInto(tmp, path, why);
}

// The family named by distortion_model; a file without one is radtan, or unified when it has a
// scalar xi (cv::omnidir's omni_calibration output).
bool ParseOpenCvFamily(const std::string& path, const cv::FileStorage& in, LensFamily* family,
                       std::string* why) {
  std::string name;
  in["distortion_model"] >> name;
  if (name.empty()) {
    *family = in["xi"].empty() ? LensFamily::kRadTan : LensFamily::kUnified;
  } else if (name == "radtan" || name == "plumb_bob") {
    *family = LensFamily::kRadTan;
  } else if (name == "equidistant" || name == "fisheye") {
    *family = LensFamily::kEquidistant;
  } else if (name == "unified" || name == "omnidir") {
    *family = LensFamily::kUnified;
  } else if (name == "eucm") {
    *family = LensFamily::kEucm;
  } else if (name == "double-sphere") {
    *family = LensFamily::kDoubleSphere;
  } else {
    return Fail(why, path + ": distortion_model: unknown '" + name +
                         "' (radtan, plumb_bob, equidistant, fisheye, unified, omnidir, eucm, "
                         "double-sphere)");
  }
  return true;
}

// A scalar lens field of the family (xi, alpha, beta): present and a number.
bool ReadScalar(const std::string& path, const cv::FileStorage& in, const char* field,
                const char* family, double* value, std::string* why) {
  const cv::FileNode node = in[field];
  if (node.empty() || !(node.isReal() || node.isInt())) {
    return Fail(why,
                path + ": " + field + ": the " + family + " model needs " + field + " (a number)");
  }
  node >> *value;
  return true;
}

// The radtan coefficients: OpenCV's 4, 5, 8, 12 or 14, the ones past k3 zero.
bool ReadRadTanCoefficients(const std::string& path, const cv::Mat& d, CameraIntrinsics* k,
                            std::string* why) {
  const int n = static_cast<int>(d.total());
  auto coeff = [&](int i) { return i < n ? d.at<double>(i) : 0.0; };
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
    return Fail(why, path + ": distortion_coefficients: OpenCV has 4, 5, 8, 12 or 14, got " +
                         std::to_string(n));
  }
  for (int i = 5; i < n; ++i) {
    if (coeff(i) != 0) {
      return Fail(why, path + ": distortion_coefficients: coefficient " + std::to_string(i) +
                           " (rational / thin-prism / tilt) is not zero; calibench's radtan "
                           "model has k1 k2 p1 p2 k3");
    }
  }
  k->k1 = coeff(0), k->k2 = coeff(1), k->p1 = coeff(2), k->p2 = coeff(3), k->k3 = coeff(4);
  return true;
}

// Exactly `count` distortion coefficients for `family` (which has them as `names`).
bool ReadCoefficients(const std::string& path, const cv::Mat& d, int count, const char* family,
                      const char* names, double* const* fields, std::string* why) {
  const int n = static_cast<int>(d.total());
  if (n != count) {
    return Fail(why, path + ": distortion_coefficients: the " + family + " model has " +
                         std::to_string(count) + " (" + names + "), got " + std::to_string(n));
  }
  for (int i = 0; i < n; ++i) *fields[i] = d.at<double>(i);
  return true;
}

// The lens fields of WriteOpenCvLens, for k->family.
bool ReadOpenCvLens(const std::string& path, const cv::FileStorage& in, CameraIntrinsics* k,
                    std::string* why) {
  cv::Mat d;
  const cv::FileNode node = in["distortion_coefficients"];
  if (node.isSeq()) {  // A plain list, as hand-written files have it.
    std::vector<double> list;
    node >> list;
    d = cv::Mat(list, true);
  } else if (node.isMap()) {
    node >> d;
  } else if (!node.empty()) {
    return Fail(why, path + ": distortion_coefficients: expected a matrix or a list of numbers");
  }
  d.convertTo(d, CV_64F);
  const char* family = ToString(k->family);
  switch (k->family) {
    case LensFamily::kRadTan:
      return ReadRadTanCoefficients(path, d, k, why);
    case LensFamily::kEquidistant: {
      double* const fields[4] = {&k->k1, &k->k2, &k->k3, &k->k4};
      return ReadCoefficients(path, d, 4, family, "k1..k4", fields, why);
    }
    case LensFamily::kUnified: {
      double* const fields[4] = {&k->k1, &k->k2, &k->p1, &k->p2};
      return ReadCoefficients(path, d, 4, family, "k1 k2 p1 p2", fields, why) &&
             ReadScalar(path, in, "xi", family, &k->xi, why);
    }
    case LensFamily::kEucm:
      return ReadCoefficients(path, d, 0, family, "none: alpha and beta", nullptr, why) &&
             ReadScalar(path, in, "alpha", family, &k->alpha, why) &&
             ReadScalar(path, in, "beta", family, &k->beta, why);
    case LensFamily::kDoubleSphere:
      return ReadCoefficients(path, d, 0, family, "none: xi and alpha", nullptr, why) &&
             ReadScalar(path, in, "xi", family, &k->xi, why) &&
             ReadScalar(path, in, "alpha", family, &k->alpha, why);
  }
  return false;
}

// camera_matrix as an upper-triangular A with fx, fy > 0.
bool ReadCameraMatrix(const std::string& path, const cv::FileStorage& in, CameraIntrinsics* k,
                      std::string* why) {
  cv::Mat a;
  in["camera_matrix"] >> a;
  if (a.rows != 3 || a.cols != 3)
    return Fail(why, path + ": camera_matrix: expected a 3 x 3 matrix");
  a.convertTo(a, CV_64F);
  Eigen::Matrix3d matrix;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) matrix(r, c) = a.at<double>(r, c);
  }
  if (!(matrix(0, 0) > 0 && matrix(1, 1) > 0) || matrix(1, 0) != 0 || matrix(2, 0) != 0 ||
      matrix(2, 1) != 0 || matrix(2, 2) != 1) {
    return Fail(why, path + ": camera_matrix: expected [fx s cx; 0 fy cy; 0 0 1] with fx, fy > 0");
  }
  *k = CameraIntrinsics::FromMatrix(matrix);
  return true;
}

// calibench's own fields: the exact pinhole values, size, RMS, std_*, view RMS, model.
bool ReadOpenCvExtras(const std::string& path, const cv::FileStorage& in, CameraFile* camera,
                      std::string* why) {
  CameraIntrinsics& k = camera->intrinsics;
  if (!in["fku_px"].empty()) in["fku_px"] >> k.fku_px;  // The matrix loses the last bits of
  if (!in["fkv_px"].empty()) in["fkv_px"] >> k.fkv_px;  // fkv and phi.
  if (!in["phi_deg"].empty()) in["phi_deg"] >> k.phi_deg;
  in["image_width"] >> camera->image_width;
  in["image_height"] >> camera->image_height;
  if (!in["rms_reproj_px"].empty()) in["rms_reproj_px"] >> camera->rms_reproj_px;
  camera->intrinsics_std.fill(std::nan(""));
  for (int i = 0; i < 10; ++i) {
    const std::string name = StdName(k.family, i);
    const cv::FileNode node = name.empty() ? cv::FileNode() : in[name];
    if (node.empty()) continue;
    double s = 0;
    node >> s;
    camera->intrinsics_std[i] = i == 2 ? s / kRadToDeg : s;
  }
  if (!in["view_rms_px"].empty()) in["view_rms_px"] >> camera->view_rms_px;
  InferModel(camera);
  std::string model;
  in["model"] >> model;
  if (model.empty()) return true;
  const size_t plus = model.find("+skew");
  if (!ParseLensModel(model.substr(0, plus), &camera->lens_model)) {
    return Fail(why, path + ": model: unknown lens model '" + model + "'");
  }
  if (FamilyOf(camera->lens_model) != k.family) {
    return Fail(why, path + ": model: '" + model + "' is not of the " + ToString(k.family) +
                         " family that distortion_model names");
  }
  camera->estimate_skew = plus != std::string::npos;
  return true;
}

bool ReadOpenCv(const std::string& path, CameraFile* camera, std::string* why) {
  try {
    cv::FileStorage in(path, cv::FileStorage::READ);
    if (!in.isOpened()) return Fail(why, path + ": cannot open (not an OpenCV FileStorage file)");
    CameraIntrinsics& k = camera->intrinsics;
    LensFamily family = LensFamily::kRadTan;
    if (!ReadCameraMatrix(path, in, &k, why) || !ParseOpenCvFamily(path, in, &family, why)) {
      return false;
    }
    k.family = family;
    return ReadOpenCvLens(path, in, &k, why) && ReadOpenCvExtras(path, in, camera, why);
  } catch (const cv::Exception& e) {
    return Fail(why, path + ": " + e.what());
  }
}

// ---- kalibr ---------------------------------------------------------------------------------

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
  camera->intrinsics = k;
  camera->image_width = static_cast<int>(res[0]);
  camera->image_height = static_cast<int>(res[1]);
  camera->intrinsics_std.fill(std::nan(""));
  InferModel(camera);
  return true;
}

// ---- mrcal ----------------------------------------------------------------------------------

bool WriteMrcal(const std::string& path, const CameraFile& camera, std::string* why) {
  const CameraIntrinsics& k = camera.intrinsics;
  if (HasSkew(k)) {
    return Fail(why, path + ": mrcal: mrcal's lens models have no skew (phi_deg " +
                         Number(k.phi_deg) + "); calibrate without --skew or write opencv");
  }
  if (k.family != LensFamily::kRadTan) {
    const std::string model =
        k.family == LensFamily::kEquidistant
            ? "Kannala-Brandt (equidistant)"
            : std::string(ToString(k.family)) + (k.family == LensFamily::kUnified ? " (Mei)" : "");
    return Fail(why, path + ": mrcal: mrcal 2.2 has no " + model +
                         " lens model (LENSMODEL_PINHOLE, STEREOGRAPHIC, LONLAT, LATLON, "
                         "OPENCV4/5/8/12, CAHVOR, CAHVORE, SPLINED_STEREOGRAPHIC); write opencv "
                         "or kalibr");
  }
  std::vector<double> intrinsics = {k.fku_px, k.fkv_px, k.u0_px, k.v0_px};
  std::string lensmodel = "LENSMODEL_PINHOLE";
  if (k.k3 != 0) {
    lensmodel = "LENSMODEL_OPENCV5";
    intrinsics.insert(intrinsics.end(), {k.k1, k.k2, k.p1, k.p2, k.k3});
  } else if (k.IsDistorted()) {
    lensmodel = "LENSMODEL_OPENCV4";
    intrinsics.insert(intrinsics.end(), {k.k1, k.k2, k.p1, k.p2});
  }
  std::ostringstream out;
  out << "# generated by calibench calibrate (" << camera.ModelName() << ", rms_reproj_px "
      << Number(camera.rms_reproj_px) << ")\n{\n    'lensmodel':  '" << lensmodel
      << "',\n    # intrinsics are fx,fy,cx,cy,distortion0,distortion1,....\n    'intrinsics': [";
  for (size_t i = 0; i < intrinsics.size(); ++i) out << (i ? ", " : " ") << Number(intrinsics[i]);
  out << " ],\n    # extrinsics are rt_fromref\n    'extrinsics': [ 0, 0, 0, 0, 0, 0 ],\n"
      << "    'imagersize': [ " << camera.image_width << ", " << camera.image_height << " ],\n}\n";
  return WriteText(path, out.str(), why);
}

// The value after 'key': in a Python-literal dict (comments already stripped): a quoted string or
// a [ ... ] list, as text.
bool DictValue(const std::string& text, const std::string& key, std::string* value) {
  for (const char quote : {'\'', '"'}) {
    const size_t at = text.find(quote + key + quote);
    if (at == std::string::npos) continue;
    size_t i = text.find(':', at + key.size() + 2);
    if (i == std::string::npos) return false;
    i = text.find_first_not_of(" \t\r\n", i + 1);
    if (i == std::string::npos) return false;
    const char open = text[i];
    const char close = open == '[' ? ']' : open;
    if (open != '[' && open != '\'' && open != '"') return false;
    const size_t end = text.find(close, i + 1);
    if (end == std::string::npos) return false;
    *value = text.substr(i + 1, end - i - 1);
    return true;
  }
  return false;
}

bool ParseList(const std::string& list, std::vector<double>* values) {
  values->clear();
  std::string item;
  std::istringstream in(list);
  while (std::getline(in, item, ',')) {
    const size_t b = item.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) continue;  // A trailing comma.
    try {
      size_t used = 0;
      const std::string token = item.substr(b, item.find_last_not_of(" \t\r\n") - b + 1);
      values->push_back(std::stod(token, &used));
      if (used != token.size()) return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  return true;
}

bool ReadMrcal(const std::string& path, const std::string& raw, CameraFile* camera,
               std::string* why) {
  std::string text;  // Without # comments.
  std::istringstream lines(raw);
  for (std::string line; std::getline(lines, line);) text += line.substr(0, line.find('#')) + "\n";
  std::string lensmodel, list;
  if (!DictValue(text, "lensmodel", &lensmodel)) {
    return Fail(why, path + ": lensmodel: missing or not a quoted string");
  }
  std::vector<double> v, size;
  if (!DictValue(text, "intrinsics", &list) || !ParseList(list, &v)) {
    return Fail(why, path + ": intrinsics: missing or not a list of numbers");
  }
  if (!DictValue(text, "imagersize", &list) || !ParseList(list, &size) || size.size() != 2) {
    return Fail(why, path + ": imagersize: missing or not [width, height]");
  }
  const struct {
    const char* name;
    size_t count;
  } known[] = {{"LENSMODEL_PINHOLE", 4},
               {"LENSMODEL_OPENCV4", 8},
               {"LENSMODEL_OPENCV5", 9},
               {"LENSMODEL_OPENCV8", 12}};
  size_t expected = 0;
  for (const auto& m : known) {
    if (lensmodel == m.name) expected = m.count;
  }
  if (expected == 0) {
    return Fail(why, path + ": lensmodel: '" + lensmodel +
                         "' has no calibench counterpart (calibench reads LENSMODEL_PINHOLE, "
                         "LENSMODEL_OPENCV4, LENSMODEL_OPENCV5 and LENSMODEL_OPENCV8 with k4..k6 "
                         "= 0)");
  }
  if (v.size() != expected) {
    return Fail(why, path + ": intrinsics: " + lensmodel + " has " + std::to_string(expected) +
                         " values, got " + std::to_string(v.size()));
  }
  for (size_t i = 9; i < v.size(); ++i) {
    if (v[i] != 0) {
      return Fail(why, path +
                           ": intrinsics: LENSMODEL_OPENCV8's rational terms k4..k6 must be 0 "
                           "(calibench's radtan has k1 k2 p1 p2 k3)");
    }
  }
  CameraIntrinsics k;
  k.fku_px = v[0], k.fkv_px = v[1], k.u0_px = v[2], k.v0_px = v[3];
  if (v.size() > 4) k.k1 = v[4], k.k2 = v[5], k.p1 = v[6], k.p2 = v[7];
  if (v.size() > 8) k.k3 = v[8];
  camera->intrinsics = k;
  camera->image_width = static_cast<int>(size[0]);
  camera->image_height = static_cast<int>(size[1]);
  camera->intrinsics_std.fill(std::nan(""));
  InferModel(camera);
  return true;
}

}  // namespace

std::string CameraFile::ModelName() const {
  return std::string(ToString(lens_model)) + (estimate_skew ? "+skew" : "");
}

const char* ToString(CameraFormat format) {
  switch (format) {
    case CameraFormat::kOpenCv:
      return "opencv";
    case CameraFormat::kKalibr:
      return "kalibr";
    case CameraFormat::kMrcal:
      return "mrcal";
  }
  return "opencv";
}

bool ParseCameraFormat(const std::string& name, CameraFormat* format, std::string* why) {
  for (CameraFormat f : {CameraFormat::kOpenCv, CameraFormat::kKalibr, CameraFormat::kMrcal}) {
    if (name == ToString(f)) {
      *format = f;
      return true;
    }
  }
  return Fail(why, "unknown camera file format '" + name + "' (opencv, kalibr, mrcal)");
}

CameraFormat CameraFormatFromPath(const std::string& path) {
  const fs::path p(path);
  const std::string name = p.filename().string();
  if (p.extension() == ".cameramodel") return CameraFormat::kMrcal;
  const bool yaml = p.extension() == ".yaml" || p.extension() == ".yml";
  if (yaml &&
      (name.find("camchain") != std::string::npos || name.find(".kalibr.") != std::string::npos)) {
    return CameraFormat::kKalibr;
  }
  return CameraFormat::kOpenCv;
}

bool WriteCameraFile(const std::string& path, CameraFormat format, const CameraFile& camera,
                     std::string* why) {
  std::string reason;
  if (!camera.intrinsics.Check(&reason)) return Fail(why, path + ": " + reason);
  switch (format) {
    case CameraFormat::kOpenCv:
      return WriteOpenCv(path, camera, why);
    case CameraFormat::kKalibr:
      return WriteKalibr(path, camera, why);
    case CameraFormat::kMrcal:
      return WriteMrcal(path, camera, why);
  }
  return Fail(why, path + ": unknown format");
}

bool ReadCameraFile(const std::string& path, CameraFile* camera, std::string* why) {
  *camera = CameraFile();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Fail(why, path + ": no such file");
  if (fs::file_size(path, ec) > (16u << 20)) return Fail(why, path + ": larger than 16 MiB");
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const std::string raw = text.str();
  bool ok = false;
  if (raw.find("lensmodel") != std::string::npos) {
    ok = ReadMrcal(path, raw, camera, why);
  } else if (raw.rfind("%YAML", 0) == 0 || raw.rfind("<?xml", 0) == 0 || raw.rfind('{', 0) == 0) {
    ok = ReadOpenCv(path, camera, why);
  } else {
    YAML::Node root;
    try {
      root = YAML::Load(raw);
    } catch (const YAML::Exception& e) {
      return Fail(why, path + ": (yaml): " + e.what());
    }
    ok = root.IsMap() && root["cam0"] ? ReadKalibr(path, root, camera, why)
                                      : ReadOpenCv(path, camera, why);
  }
  if (!ok) return false;
  std::string reason;
  if (!camera->intrinsics.Check(&reason)) return Fail(why, path + ": " + reason);
  if (camera->image_width <= 0 || camera->image_height <= 0) {
    return Fail(why, path + ": image size: expected positive width and height");
  }
  return true;
}

}  // namespace calibench
