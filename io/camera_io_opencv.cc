#include <Eigen/Eigenvalues>
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
void WriteOpenCvLens(const CameraIntrinsics& k, const OpenCvFieldName& name, cv::FileStorage* out) {
  switch (k.family) {
    case LensFamily::kRadTan:
      *out << name("distortion_coefficients")
           << (cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3);
      return;
    case LensFamily::kEquidistant:
      *out << name("distortion_coefficients") << (cv::Mat_<double>(1, 4) << k.k1, k.k2, k.k3, k.k4);
      return;
    case LensFamily::kUnified:
      *out << name("distortion_coefficients") << (cv::Mat_<double>(1, 4) << k.k1, k.k2, k.p1, k.p2);
      *out << name("xi") << k.xi;
      return;
    case LensFamily::kEucm:
      *out << name("alpha") << k.alpha << name("beta") << k.beta;
      return;
    case LensFamily::kDoubleSphere:
      *out << name("xi") << k.xi << name("alpha") << k.alpha;
      return;
  }
}

std::string SameName(const std::string& field) { return field; }

void WriteOpenCvCamera(const CameraFile& camera, bool with_fit, const OpenCvFieldName& name,
                       cv::FileStorage* out_storage) {
  cv::FileStorage& out = *out_storage;
  const CameraIntrinsics& k = camera.intrinsics;
  const Eigen::Matrix3d a = k.Matrix();
  cv::Mat camera_matrix(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) camera_matrix.at<double>(r, c) = a(r, c);
  }
  out << name("model") << camera.ModelName();
  out << name("image_width") << camera.image_width << name("image_height") << camera.image_height;
  out << name("camera_matrix") << camera_matrix;
  out << name("distortion_model") << ToString(k.family);
  WriteOpenCvLens(k, name, &out);
  out << name("fku_px") << k.fku_px << name("fkv_px") << k.fkv_px << name("phi_deg") << k.phi_deg;
  if (with_fit) out << name("rms_reproj_px") << camera.rms_reproj_px;
  for (int i = 0; i < 10; ++i) {
    const double s = camera.intrinsics_std[i];
    const std::string std_name = StdName(k.family, i);
    if (std::isfinite(s) && !std_name.empty()) {
      out << name(std_name) << (i == 2 ? s * kRadToDeg : s);
    }
  }
  if (with_fit) out << name("view_rms_px") << camera.view_rms_px;
  if (with_fit && camera.projection.IsSet()) {
    cv::Mat covariance(ProjectionCovariance::kSize, ProjectionCovariance::kSize, CV_64F);
    for (int r = 0; r < ProjectionCovariance::kSize; ++r) {
      for (int c = 0; c < ProjectionCovariance::kSize; ++c) {
        covariance.at<double>(r, c) = camera.projection.covariance(r, c);
      }
    }
    out << name("projection_covariance") << covariance;
    out << name("projection_sigma_px") << camera.projection.sigma_px;
    out << name("projection_views") << camera.projection.num_views;
    out << name("projection_scale") << camera.projection_scale;
    out << name("projection_source") << camera.projection_source;
  }
}

bool WriteOpenCv(const std::string& path, const CameraFile& camera, std::string* why) {
  const std::string tmp = TemporaryBeside(path);
  try {
    cv::FileStorage out(tmp, cv::FileStorage::WRITE);
    if (!out.isOpened()) return Fail(why, path + ": cannot open for writing");
    WriteOpenCvCamera(camera, /*with_fit=*/true, SameName, &out);
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
bool ParseOpenCvFamily(const std::string& path, const cv::FileStorage& in,
                       const OpenCvFieldName& field, LensFamily* family, std::string* why) {
  std::string name;
  in[field("distortion_model")] >> name;
  if (name.empty()) {
    *family = in[field("xi")].empty() ? LensFamily::kRadTan : LensFamily::kUnified;
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
  return Fail(why,
              path + ": " + field("distortion_model") + ": unknown '" + name + "' (" + known + ")");
}

// A scalar lens field of the family (xi, alpha, beta): present and a number.
bool ReadScalar(const std::string& path, const cv::FileStorage& in, const std::string& field,
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
bool ReadRadTanCoefficients(const std::string& path, const std::string& field, const cv::Mat& d,
                            CameraIntrinsics* k, std::string* why) {
  const int n = static_cast<int>(d.total());
  auto coeff = [&](int i) { return i < n ? d.at<double>(i) : 0.0; };
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
    return Fail(why,
                path + ": " + field + ": OpenCV has 4, 5, 8, 12 or 14, got " + std::to_string(n));
  }
  for (int i = 5; i < n; ++i) {
    if (coeff(i) != 0) {
      return Fail(why, path + ": " + field + ": coefficient " + std::to_string(i) +
                           " (rational / thin-prism / tilt) is not zero; calibench's radtan "
                           "model has k1 k2 p1 p2 k3");
    }
  }
  k->k1 = coeff(0), k->k2 = coeff(1), k->p1 = coeff(2), k->p2 = coeff(3), k->k3 = coeff(4);
  return true;
}

// Exactly `count` distortion coefficients for `family` (which has them as `names`).
bool ReadCoefficients(const std::string& path, const std::string& field, const cv::Mat& d,
                      int count, const char* family, const char* names, double* const* fields,
                      std::string* why) {
  const int n = static_cast<int>(d.total());
  if (n != count) {
    return Fail(why, path + ": " + field + ": the " + family + " model has " +
                         std::to_string(count) + " (" + names + "), got " + std::to_string(n));
  }
  for (int i = 0; i < n; ++i) *fields[i] = d.at<double>(i);
  return true;
}

// The lens fields of WriteOpenCvLens, for k->family.
bool ReadOpenCvLens(const std::string& path, const cv::FileStorage& in, const OpenCvFieldName& name,
                    CameraIntrinsics* k, std::string* why) {
  cv::Mat d;
  const std::string coefficients = name("distortion_coefficients");
  const cv::FileNode node = in[coefficients];
  if (node.isSeq()) {  // A plain list, as hand-written files have it.
    std::vector<double> list;
    node >> list;
    d = cv::Mat(list, true);
  } else if (node.isMap()) {
    node >> d;
  } else if (!node.empty()) {
    return Fail(why, path + ": " + coefficients + ": expected a matrix or a list of numbers");
  }
  d.convertTo(d, CV_64F);
  const char* family = ToString(k->family);
  switch (k->family) {
    case LensFamily::kRadTan:
      return ReadRadTanCoefficients(path, coefficients, d, k, why);
    case LensFamily::kEquidistant: {
      double* const fields[4] = {&k->k1, &k->k2, &k->k3, &k->k4};
      return ReadCoefficients(path, coefficients, d, 4, family, "k1..k4", fields, why);
    }
    case LensFamily::kUnified: {
      double* const fields[4] = {&k->k1, &k->k2, &k->p1, &k->p2};
      return ReadCoefficients(path, coefficients, d, 4, family, "k1 k2 p1 p2", fields, why) &&
             ReadScalar(path, in, name("xi"), family, &k->xi, why);
    }
    case LensFamily::kEucm:
      return ReadCoefficients(path, coefficients, d, 0, family, "none: alpha and beta", nullptr,
                              why) &&
             ReadScalar(path, in, name("alpha"), family, &k->alpha, why) &&
             ReadScalar(path, in, name("beta"), family, &k->beta, why);
    case LensFamily::kDoubleSphere:
      return ReadCoefficients(path, coefficients, d, 0, family, "none: xi and alpha", nullptr,
                              why) &&
             ReadScalar(path, in, name("xi"), family, &k->xi, why) &&
             ReadScalar(path, in, name("alpha"), family, &k->alpha, why);
  }
  return false;
}

// camera_matrix as an upper-triangular A with fx, fy > 0.
bool ReadCameraMatrix(const std::string& path, const cv::FileStorage& in,
                      const OpenCvFieldName& name, CameraIntrinsics* k, std::string* why) {
  cv::Mat a;
  in[name("camera_matrix")] >> a;
  if (a.rows != 3 || a.cols != 3)
    return Fail(why, path + ": " + name("camera_matrix") + ": expected a 3 x 3 matrix");
  a.convertTo(a, CV_64F);
  Eigen::Matrix3d matrix;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) matrix(r, c) = a.at<double>(r, c);
  }
  if (!(matrix(0, 0) > 0 && matrix(1, 1) > 0) || matrix(1, 0) != 0 || matrix(2, 0) != 0 ||
      matrix(2, 1) != 0 || matrix(2, 2) != 1) {
    return Fail(why, path + ": " + name("camera_matrix") +
                         ": expected [fx s cx; 0 fy cy; 0 0 1] with fx, fy > 0");
  }
  *k = CameraIntrinsics::FromMatrix(matrix);
  return true;
}

// projection_covariance (16 x 16, symmetric, finite, non-negative diagonal), projection_sigma_px,
// projection_views, projection_scale: the projection uncertainty's Cov(z), when present.
bool ReadProjectionCovariance(const std::string& path, const cv::FileStorage& in,
                              const OpenCvFieldName& field, CameraFile* camera, std::string* why) {
  const cv::FileNode node = in[field("projection_covariance")];
  if (node.empty()) return true;
  constexpr int kSize = ProjectionCovariance::kSize;
  const std::string name = path + ": " + field("projection_covariance");
  cv::Mat covariance;
  try {
    node >> covariance;
  } catch (const cv::Exception&) {
    return Fail(why, name + ": expected a 16 x 16 matrix of doubles (rows, cols and data differ)");
  }
  if (covariance.rows != kSize || covariance.cols != kSize || covariance.type() != CV_64F) {
    return Fail(why, name + ": expected a 16 x 16 matrix of doubles");
  }
  ProjectionCovariance& p = camera->projection;
  for (int r = 0; r < kSize; ++r) {
    for (int c = 0; c < kSize; ++c) p.covariance(r, c) = covariance.at<double>(r, c);
  }
  const double scale = p.covariance.cwiseAbs().maxCoeff();
  const bool symmetric =
      p.covariance.allFinite() &&
      (p.covariance - p.covariance.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale;
  if (!symmetric || !(scale > 0) ||
      Eigen::SelfAdjointEigenSolver<ProjectionCovariance::Matrix>(p.covariance)
              .eigenvalues()
              .minCoeff() < -1e-9 * scale) {
    p = ProjectionCovariance();
    return Fail(why, name +
                         ": expected a finite, symmetric, positive semi-definite and non-zero "
                         "covariance");
  }
  const cv::FileNode views = in[field("projection_views")];
  const cv::FileNode sigma = in[field("projection_sigma_px")];
  p.num_views = views.empty() ? 1 : static_cast<int>(views);
  if (!sigma.empty()) sigma >> p.sigma_px;
  const cv::FileNode applied = in[field("projection_scale")];
  if (!applied.empty()) applied >> camera->projection_scale;
  const cv::FileNode source = in[field("projection_source")];
  if (!source.empty()) source >> camera->projection_source;
  if (p.num_views < 1 || !(camera->projection_scale >= 1.0)) {
    p = ProjectionCovariance();
    return Fail(why, path + ": " + field("projection_views") + " / " + field("projection_scale") +
                         ": expected at least 1");
  }
  return true;
}

// calibench's own fields: the exact pinhole values, size, RMS, std_*, view RMS, model.
bool ReadOpenCvExtras(const std::string& path, const cv::FileStorage& in,
                      const OpenCvFieldName& field, CameraFile* camera, std::string* why) {
  CameraIntrinsics& k = camera->intrinsics;
  const auto read = [&](const char* name, auto* value) {
    const cv::FileNode node = in[field(name)];
    if (!node.empty()) node >> *value;
  };
  read("fku_px", &k.fku_px);  // The matrix loses the last bits of fkv and phi.
  read("fkv_px", &k.fkv_px);
  read("phi_deg", &k.phi_deg);
  in[field("image_width")] >> camera->image_width;
  in[field("image_height")] >> camera->image_height;
  read("rms_reproj_px", &camera->rms_reproj_px);
  camera->intrinsics_std.fill(std::nan(""));
  for (int i = 0; i < 10; ++i) {
    const std::string name = StdName(k.family, i);
    const cv::FileNode node = name.empty() ? cv::FileNode() : in[field(name)];
    if (node.empty()) continue;
    double s = 0;
    node >> s;
    camera->intrinsics_std[i] = i == 2 ? s / kRadToDeg : s;
  }
  read("view_rms_px", &camera->view_rms_px);
  if (!ReadProjectionCovariance(path, in, field, camera, why)) return false;
  InferModel(camera);
  std::string model;
  in[field("model")] >> model;
  if (model.empty()) return true;
  const size_t plus = model.find("+skew");
  if (!ParseLensModel(model.substr(0, plus), &camera->lens_model)) {
    return Fail(why, path + ": " + field("model") + ": unknown lens model '" + model + "'");
  }
  if (FamilyOf(camera->lens_model) != k.family) {
    return Fail(why, path + ": " + field("model") + ": '" + model + "' is not of the " +
                         ToString(k.family) + " family that " + field("distortion_model") +
                         " names");
  }
  camera->estimate_skew = plus != std::string::npos;
  return true;
}

bool ReadOpenCvCamera(const std::string& path, const cv::FileStorage& in,
                      const OpenCvFieldName& name, CameraFile* camera, std::string* why) {
  CameraIntrinsics& k = camera->intrinsics;
  LensFamily family = LensFamily::kRadTan;
  if (!ReadCameraMatrix(path, in, name, &k, why) ||
      !ParseOpenCvFamily(path, in, name, &family, why)) {
    return false;
  }
  k.family = family;
  return ReadOpenCvLens(path, in, name, &k, why) && ReadOpenCvExtras(path, in, name, camera, why);
}

bool ReadOpenCv(const std::string& path, CameraFile* camera, std::string* why,
                const std::string& yaml_text) {
  try {
    // OpenCV refuses a YAML file without its "%YAML:1.0" line: a hand-written file is read from
    // memory with the line added.
    cv::FileStorage in = yaml_text.empty()
                             ? cv::FileStorage(path, cv::FileStorage::READ)
                             : cv::FileStorage("%YAML:1.0\n" + yaml_text,
                                               cv::FileStorage::READ | cv::FileStorage::MEMORY |
                                                   cv::FileStorage::FORMAT_YAML);
    if (!in.isOpened()) return Fail(why, path + ": cannot open (not an OpenCV FileStorage file)");
    return ReadOpenCvCamera(path, in, SameName, camera, why);
  } catch (const cv::Exception& e) {
    return Fail(why, path +
                         ": not a camera file calibench reads (an OpenCV YAML/XML/JSON file with "
                         "camera_matrix, a Kalibr camchain or an mrcal .cameramodel): OpenCV "
                         "cannot parse it (" +
                         e.err + ")");
  }
}

}  // namespace camera_io_internal
}  // namespace calibench
