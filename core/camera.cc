#include "core/camera.h"

#include <algorithm>
#include <sstream>

namespace calibench {
namespace {
constexpr double kDegToRad = M_PI / 180.0;
}  // namespace

bool CameraIntrinsics::Check(std::string* why) const {
  std::ostringstream msg;
  if (!(std::isfinite(fku_px) && fku_px > 0)) {
    msg << "fku_px must be a positive focal length in pixels, got " << fku_px;
  } else if (!(std::isfinite(fkv_px) && fkv_px > 0)) {
    msg << "fkv_px must be a positive focal length in pixels, got " << fkv_px;
  } else if (!(phi_deg > 0 && phi_deg < 180)) {
    msg << "phi_deg must lie in (0, 180) degrees (90 = no skew), got " << phi_deg;
  } else if (!std::isfinite(u0_px) || !std::isfinite(v0_px)) {
    msg << "principal point must be finite, got (" << u0_px << ", " << v0_px << ")";
  } else if (!std::isfinite(k1) || !std::isfinite(k2) || !std::isfinite(k3) || !std::isfinite(p1) ||
             !std::isfinite(p2)) {
    msg << "distortion coefficients must be finite, got k1 " << k1 << ", k2 " << k2 << ", p1 " << p1
        << ", p2 " << p2 << ", k3 " << k3;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

Eigen::Matrix3d CameraIntrinsics::Matrix() const {
  const double phi = phi_deg * kDegToRad;
  Eigen::Matrix3d a;
  a << fku_px, -fku_px * std::cos(phi) / std::sin(phi), u0_px,  //
      0, fkv_px / std::sin(phi), v0_px,                         //
      0, 0, 1;
  return a;
}

CameraIntrinsics CameraIntrinsics::FromMatrix(const Eigen::Matrix3d& a) {
  CameraIntrinsics k;
  const double phi = std::atan2(a(0, 0), -a(0, 1));  // in (0, pi) for a1 > 0.
  k.fku_px = a(0, 0);
  k.phi_deg = phi / kDegToRad;
  k.fkv_px = a(1, 1) * std::sin(phi);
  k.u0_px = a(0, 2);
  k.v0_px = a(1, 2);
  return k;
}

std::array<double, 10> CameraIntrinsics::Params() const {
  return {fku_px, fkv_px, phi_deg * kDegToRad, u0_px, v0_px, k1, k2, p1, p2, k3};
}

CameraIntrinsics CameraIntrinsics::FromParams(const double* params) {
  CameraIntrinsics k;
  k.fku_px = params[0];
  k.fkv_px = params[1];
  k.phi_deg = params[2] / kDegToRad;
  k.u0_px = params[3];
  k.v0_px = params[4];
  k.k1 = params[5];
  k.k2 = params[6];
  k.p1 = params[7];
  k.p2 = params[8];
  k.k3 = params[9];
  return k;
}

bool ProjectPoint(const CameraIntrinsics& intrinsics, const Eigen::Vector3d& point_in_cam,
                  Eigen::Vector2d* pixel) {
  const std::array<double, 10> params = intrinsics.Params();
  return PinholeSkewCamera::Project(params.data(), point_in_cam.data(), pixel->data());
}

bool operator==(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return a.Params() == b.Params();
}

const std::vector<LensModelInfo>& LensModels() {
  static const std::vector<LensModelInfo> models = {
      {LensModel::kPinhole, "pinhole", {}},
      {LensModel::kPinholeK2, "pinhole-k2", {5, 6}},
      {LensModel::kPinholeRadTan4, "pinhole-radtan4", {5, 6, 7, 8}},
      {LensModel::kPinholeRadTan5, "pinhole-radtan5", {5, 6, 7, 8, 9}},
  };
  return models;
}

const char* ToString(LensModel model) {
  for (const LensModelInfo& info : LensModels()) {
    if (info.model == model) return info.name;
  }
  return "pinhole";
}

bool ParseLensModel(const std::string& name, LensModel* model) {
  for (const LensModelInfo& info : LensModels()) {
    if (name == info.name) {
      *model = info.model;
      return true;
    }
  }
  return false;
}

std::vector<std::string> LensModelNames() {
  std::vector<std::string> names;
  for (const LensModelInfo& info : LensModels()) names.emplace_back(info.name);
  return names;
}

std::vector<int> FixedIntrinsics(LensModel model, bool estimate_skew) {
  std::vector<int> fixed;
  if (!estimate_skew) fixed.push_back(2);
  for (const LensModelInfo& info : LensModels()) {
    if (info.model != model) continue;
    for (int i = 5; i < PinholeSkewCamera::kNumParams; ++i) {
      if (std::find(info.free_distortion.begin(), info.free_distortion.end(), i) ==
          info.free_distortion.end()) {
        fixed.push_back(i);
      }
    }
  }
  return fixed;
}

}  // namespace calibench
