#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>

#include "io/camera_io_formats.h"

namespace calibench {
namespace camera_io_internal {
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
    std::filesystem::remove(tmp, ec);
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
    return true;
  }
  std::string known;  // Every family's name and OpenCV's alias (LensFamilyInfo::opencv_alias).
  for (const LensFamilyInfo& info : LensFamilies()) {
    const bool alias = info.opencv_alias != nullptr;
    if (name == info.name || (alias && name == info.opencv_alias)) {
      *family = info.family;
      return true;
    }
    known += (known.empty() ? "" : ", ") + std::string(info.name);
    if (alias) known += ", " + std::string(info.opencv_alias);
  }
  return Fail(why, path + ": distortion_model: unknown '" + name + "' (" + known + ")");
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

}  // namespace camera_io_internal
}  // namespace calibench
