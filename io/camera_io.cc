#include "io/camera_io.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/camera_io_formats.h"

namespace calibench {
namespace camera_io_internal {

namespace fs = std::filesystem;

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

void SetCameraWithoutStd(const CameraIntrinsics& k, double width, double height,
                         CameraFile* camera) {
  camera->intrinsics = k;
  camera->image_width = static_cast<int>(width);
  camera->image_height = static_cast<int>(height);
  camera->intrinsics_std.fill(std::nan(""));
  InferModel(camera);
}

}  // namespace camera_io_internal

namespace {

namespace fs = std::filesystem;
using camera_io_internal::Fail;
using camera_io_internal::ReadKalibr;
using camera_io_internal::ReadMrcal;
using camera_io_internal::ReadOpenCv;
using camera_io_internal::WriteKalibr;
using camera_io_internal::WriteMrcal;
using camera_io_internal::WriteOpenCv;

}  // namespace

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
  if (raw.find_first_not_of(" \t\r\n") == std::string::npos) {
    return Fail(why, path + ": empty file");
  }
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
                                      : ReadOpenCv(path, camera, why, raw);
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
