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
  if (k.family == LensFamily::kEquidistant) return LensModel::kPinholeEqui;
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

const char* kStdNames[10] = {"std_fku_px", "std_fkv_px", "std_phi_deg", "std_u0_px", "std_v0_px",
                             "std_k1",     "std_k2",     "std_p1",      "std_p2",    "std_k3"};
const char* kEquiStdNames[10] = {"std_fku_px", "std_fkv_px", "std_phi_deg", "std_u0_px",
                                 "std_v0_px",  "std_k1",     "std_k2",      "std_k3",
                                 "std_k4",     "std_unused"};

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
    const bool equi = k.family == LensFamily::kEquidistant;
    out << "model" << camera.ModelName();
    out << "image_width" << camera.image_width << "image_height" << camera.image_height;
    out << "camera_matrix" << camera_matrix;
    out << "distortion_model" << ToString(k.family);
    if (equi) {
      out << "distortion_coefficients" << (cv::Mat_<double>(1, 4) << k.k1, k.k2, k.k3, k.k4);
    } else {
      out << "distortion_coefficients" << (cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3);
    }
    out << "fku_px" << k.fku_px << "fkv_px" << k.fkv_px << "phi_deg" << k.phi_deg;
    out << "rms_reproj_px" << camera.rms_reproj_px;
    for (int i = 0; i < 10; ++i) {
      const double s = camera.intrinsics_std[i];
      if (std::isfinite(s))
        out << (equi ? kEquiStdNames : kStdNames)[i] << (i == 2 ? s * kRadToDeg : s);
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

bool ReadOpenCv(const std::string& path, CameraFile* camera, std::string* why) {
  try {
    cv::FileStorage in(path, cv::FileStorage::READ);
    if (!in.isOpened()) return Fail(why, path + ": cannot open (not an OpenCV FileStorage file)");
    cv::Mat a, d;
    in["camera_matrix"] >> a;
    if (a.rows != 3 || a.cols != 3) {
      return Fail(why, path + ": camera_matrix: expected a 3 x 3 matrix");
    }
    a.convertTo(a, CV_64F);
    Eigen::Matrix3d matrix;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) matrix(r, c) = a.at<double>(r, c);
    }
    if (!(matrix(0, 0) > 0 && matrix(1, 1) > 0) || matrix(1, 0) != 0 || matrix(2, 0) != 0 ||
        matrix(2, 1) != 0 || matrix(2, 2) != 1) {
      return Fail(why,
                  path + ": camera_matrix: expected [fx s cx; 0 fy cy; 0 0 1] with fx, fy > 0");
    }
    CameraIntrinsics k = CameraIntrinsics::FromMatrix(matrix);
    std::string family;
    in["distortion_model"] >> family;
    if (family == "equidistant" || family == "fisheye") {
      k.family = LensFamily::kEquidistant;
    } else if (!family.empty() && family != "radtan" && family != "plumb_bob") {
      return Fail(why, path + ": distortion_model: unknown '" + family +
                           "' (radtan, plumb_bob, equidistant, fisheye)");
    }
    in["distortion_coefficients"] >> d;
    d.convertTo(d, CV_64F);
    const int n = static_cast<int>(d.total());
    auto coeff = [&](int i) { return i < n ? d.at<double>(i) : 0.0; };
    if (k.family == LensFamily::kEquidistant) {
      if (n != 4) {
        return Fail(why, path +
                             ": distortion_coefficients: the equidistant model has 4 (k1..k4), "
                             "got " +
                             std::to_string(n));
      }
      k.k1 = coeff(0), k.k2 = coeff(1), k.k3 = coeff(2), k.k4 = coeff(3);
    } else {
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
      k.k1 = coeff(0), k.k2 = coeff(1), k.p1 = coeff(2), k.p2 = coeff(3), k.k3 = coeff(4);
    }
    // calibench's exact fields (the matrix loses the last bits of fkv and phi).
    if (!in["fku_px"].empty()) in["fku_px"] >> k.fku_px;
    if (!in["fkv_px"].empty()) in["fkv_px"] >> k.fkv_px;
    if (!in["phi_deg"].empty()) in["phi_deg"] >> k.phi_deg;
    camera->intrinsics = k;
    in["image_width"] >> camera->image_width;
    in["image_height"] >> camera->image_height;
    if (!in["rms_reproj_px"].empty()) in["rms_reproj_px"] >> camera->rms_reproj_px;
    camera->intrinsics_std.fill(std::nan(""));
    const bool equi = k.family == LensFamily::kEquidistant;
    for (int i = 0; i < 10; ++i) {
      const cv::FileNode node = in[(equi ? kEquiStdNames : kStdNames)[i]];
      if (node.empty()) continue;
      double s = 0;
      node >> s;
      camera->intrinsics_std[i] = i == 2 ? s / kRadToDeg : s;
    }
    if (!in["view_rms_px"].empty()) in["view_rms_px"] >> camera->view_rms_px;
    InferModel(camera);
    std::string model;
    in["model"] >> model;
    if (!model.empty()) {
      const size_t plus = model.find("+skew");
      if (!ParseLensModel(model.substr(0, plus), &camera->lens_model)) {
        return Fail(why, path + ": model: unknown lens model '" + model + "'");
      }
      camera->estimate_skew = plus != std::string::npos;
    }
  } catch (const cv::Exception& e) {
    return Fail(why, path + ": " + e.what());
  }
  return true;
}

// ---- kalibr ---------------------------------------------------------------------------------

bool WriteKalibr(const std::string& path, const CameraFile& camera, std::string* why) {
  const CameraIntrinsics& k = camera.intrinsics;
  if (HasSkew(k)) {
    return Fail(why, path + ": kalibr: Kalibr's pinhole camera has no skew (phi_deg " +
                         Number(k.phi_deg) + "); calibrate without --skew or write opencv");
  }
  const bool equi = k.family == LensFamily::kEquidistant;
  if (!equi && k.k3 != 0) {
    return Fail(why, path + ": kalibr: Kalibr's radtan model has k1 k2 r1 r2, no k3 (k3 " +
                         Number(k.k3) + "); use --model pinhole-radtan4 or write opencv/mrcal");
  }
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap << YAML::Key << "cam0" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "camera_model" << YAML::Value << "pinhole";
  out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << YAML::BeginSeq << k.fku_px
      << k.fkv_px << k.u0_px << k.v0_px << YAML::EndSeq;
  out << YAML::Key << "distortion_model" << YAML::Value << (equi ? "equidistant" : "radtan");
  out << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  if (equi) {
    out << k.k1 << k.k2 << k.k3 << k.k4;
  } else {
    out << k.k1 << k.k2 << k.p1 << k.p2;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << camera.image_width << camera.image_height << YAML::EndSeq;
  out << YAML::EndMap << YAML::EndMap;
  return WriteText(path, std::string(out.c_str()) + "\n", why);
}

bool ReadKalibr(const std::string& path, const YAML::Node& root, CameraFile* camera,
                std::string* why) {
  const YAML::Node cam = root["cam0"];
  const std::string at = path + ": cam0.";
  auto numbers = [&](const char* field, size_t count, std::vector<double>* values) {
    const YAML::Node node = cam[field];
    if (!node || !node.IsSequence() || node.size() != count) {
      return Fail(why, at + field + ": expected a list of " + std::to_string(count) + " numbers");
    }
    values->clear();
    for (const YAML::Node& v : node) {
      try {
        values->push_back(v.as<double>());
      } catch (const YAML::Exception&) {
        return Fail(why, at + field + ": '" + v.Scalar() + "' is not a number");
      }
    }
    return true;
  };
  const std::string model = cam["camera_model"] ? cam["camera_model"].as<std::string>("") : "";
  if (model != "pinhole") {
    return Fail(why, at + "camera_model: '" + model +
                         "' is not supported (calibench reads Kalibr's pinhole; omni, ds and eucm "
                         "have other projections)");
  }
  std::vector<double> intr, dist, res;
  if (!numbers("intrinsics", 4, &intr) || !numbers("resolution", 2, &res)) return false;
  const std::string dist_model =
      cam["distortion_model"] ? cam["distortion_model"].as<std::string>("") : "none";
  CameraIntrinsics k;
  if (dist_model == "equidistant") {
    k.family = LensFamily::kEquidistant;
    if (!numbers("distortion_coeffs", 4, &dist)) return false;
    k.k1 = dist[0], k.k2 = dist[1], k.k3 = dist[2], k.k4 = dist[3];
  } else if (dist_model == "radtan") {
    if (!numbers("distortion_coeffs", 4, &dist)) return false;
    k.k1 = dist[0], k.k2 = dist[1], k.p1 = dist[2], k.p2 = dist[3];
  } else if (dist_model != "none") {
    return Fail(why, at + "distortion_model: '" + dist_model +
                         "' is not supported (radtan, equidistant, none)");
  }
  k.fku_px = intr[0], k.fkv_px = intr[1], k.u0_px = intr[2], k.v0_px = intr[3];
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
  if (k.family == LensFamily::kEquidistant) {
    return Fail(why, path +
                         ": mrcal: mrcal 2.2 has no Kannala-Brandt (equidistant) lens model "
                         "(LENSMODEL_PINHOLE, STEREOGRAPHIC, LONLAT, LATLON, OPENCV4/5/8/12, "
                         "CAHVOR, CAHVORE, SPLINED_STEREOGRAPHIC); write opencv or kalibr");
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
  switch (camera.intrinsics.family) {
    case LensFamily::kRadTan:
    case LensFamily::kEquidistant:
      break;
    case LensFamily::kUnified:
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere:
      return Fail(why, path + ": camera files do not support the " +
                           ToString(camera.intrinsics.family) +
                           " lens family yet (radtan and equidistant only)");
  }
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
