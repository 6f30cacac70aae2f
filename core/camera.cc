#include "core/camera.h"

#include <Eigen/Geometry>
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
             !std::isfinite(p2) || !std::isfinite(k4)) {
    msg << "distortion coefficients must be finite, got k1 " << k1 << ", k2 " << k2 << ", p1 " << p1
        << ", p2 " << p2 << ", k3 " << k3 << ", k4 " << k4;
  } else if (family == LensFamily::kRadTan && k4 != 0) {
    msg << "k4 belongs to the equidistant (fisheye) family; the radtan model has k1, k2, p1, p2, "
           "k3 (got k4 "
        << k4 << ")";
  } else if (family == LensFamily::kEquidistant && (p1 != 0 || p2 != 0)) {
    msg << "the equidistant (fisheye) model has k1..k4 and no tangential terms (got p1 " << p1
        << ", p2 " << p2 << ")";
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

bool CameraIntrinsics::DistortionIsMonotoneAt(double r2) const {
  switch (family) {
    case LensFamily::kRadTan:  // d/dr [r (1 + k1 r^2 + k2 r^4 + k3 r^6)] (radial part).
      return 1 + r2 * (3 * k1 + r2 * (5 * k2 + r2 * 7 * k3)) > 0;
    case LensFamily::kEquidistant: {  // d/dtheta [theta (1 + k1 t^2 + .. + k4 t^8)], t = theta.
      const double theta = std::atan(std::sqrt(r2)), t2 = theta * theta;
      return 1 + t2 * (3 * k1 + t2 * (5 * k2 + t2 * (7 * k3 + t2 * 9 * k4))) > 0;
    }
  }
  return false;
}

std::array<double, 10> CameraIntrinsics::Params() const {
  const double phi = phi_deg * kDegToRad;
  if (family == LensFamily::kEquidistant)
    return {fku_px, fkv_px, phi, u0_px, v0_px, k1, k2, k3, k4, 0};
  return {fku_px, fkv_px, phi, u0_px, v0_px, k1, k2, p1, p2, k3};
}

CameraIntrinsics CameraIntrinsics::FromParams(const double* params, LensFamily family) {
  CameraIntrinsics k;
  k.family = family;
  k.fku_px = params[0];
  k.fkv_px = params[1];
  k.phi_deg = params[2] / kDegToRad;
  k.u0_px = params[3];
  k.v0_px = params[4];
  k.k1 = params[5];
  k.k2 = params[6];
  if (family == LensFamily::kEquidistant) {
    k.k3 = params[7];
    k.k4 = params[8];
  } else {
    k.p1 = params[7];
    k.p2 = params[8];
    k.k3 = params[9];
  }
  return k;
}

const char* ToString(LensFamily family) {
  return family == LensFamily::kEquidistant ? "equidistant" : "radtan";
}

const std::array<const char*, 10>& ParamNames(LensFamily family) {
  static const std::array<const char*, 10> radtan = {
      "fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px", "k1", "k2", "p1", "p2", "k3"};
  static const std::array<const char*, 10> equidistant = {
      "fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px", "k1", "k2", "k3", "k4", "-"};
  return family == LensFamily::kEquidistant ? equidistant : radtan;
}

bool ProjectPoint(const CameraIntrinsics& intrinsics, const Eigen::Vector3d& point_in_cam,
                  Eigen::Vector2d* pixel) {
  const std::array<double, 10> params = intrinsics.Params();
  return ProjectLens(intrinsics.family, params.data(), point_in_cam.data(), pixel->data());
}

bool UnprojectPixel(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel,
                    Eigen::Vector2d* normalized) {
  const Eigen::Vector3d distorted = intrinsics.Matrix().inverse() * pixel.homogeneous();
  return UndistortNormalized(intrinsics, distorted.hnormalized(), normalized);
}

bool UndistortNormalized(const CameraIntrinsics& k, const Eigen::Vector2d& distorted,
                         Eigen::Vector2d* undistorted) {
  if (k.family == LensFamily::kEquidistant) {
    // theta_d = |distorted|; solve theta (1 + k1 t^2 + .. + k4 t^8) = theta_d for theta in
    // [0, pi/2) by Newton from theta = theta_d, then (x, y) = tan(theta) / theta_d * distorted.
    const double theta_d = distorted.norm();
    if (!(theta_d > 1e-15)) {
      *undistorted = distorted;
      return std::isfinite(theta_d);
    }
    double theta = std::min(theta_d, 1.5);
    for (int it = 0; it < 50; ++it) {
      const double t2 = theta * theta;
      const double f = theta * (1 + t2 * (k.k1 + t2 * (k.k2 + t2 * (k.k3 + t2 * k.k4)))) - theta_d;
      const double df = 1 + t2 * (3 * k.k1 + t2 * (5 * k.k2 + t2 * (7 * k.k3 + t2 * 9 * k.k4)));
      if (!(df > 0)) return false;  // Past the fold-over.
      const double step = f / df;
      theta -= step;
      if (!(theta >= 0 && theta < M_PI / 2)) return false;
      if (std::abs(step) < 1e-14) {
        *undistorted = distorted * (std::tan(theta) / theta_d);
        return true;
      }
    }
    return false;
  }
  Eigen::Vector2d p = distorted;
  for (int it = 0; it < 100; ++it) {
    const double x = p.x(), y = p.y(), r2 = x * x + y * y;
    const double d = 1.0 + r2 * (k.k1 + r2 * (k.k2 + r2 * k.k3));
    const double dx = 2 * k.p1 * x * y + k.p2 * (r2 + 2 * x * x);
    const double dy = k.p1 * (r2 + 2 * y * y) + 2 * k.p2 * x * y;
    const Eigen::Vector2d next((distorted.x() - dx) / d, (distorted.y() - dy) / d);
    if (!next.allFinite() || d <= 0) return false;
    const double change = (next - p).norm();
    p = next;
    if (change < 1e-12) {
      *undistorted = p;
      return true;
    }
  }
  return false;
}

bool operator==(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return a.family == b.family && a.Params() == b.Params();
}

const std::vector<LensModelInfo>& LensModels() {
  static const std::vector<LensModelInfo> models = {
      {LensModel::kPinhole, "pinhole", LensFamily::kRadTan, {}},
      {LensModel::kPinholeK2, "pinhole-k2", LensFamily::kRadTan, {5, 6}},
      {LensModel::kPinholeRadTan4, "pinhole-radtan4", LensFamily::kRadTan, {5, 6, 7, 8}},
      {LensModel::kPinholeRadTan5, "pinhole-radtan5", LensFamily::kRadTan, {5, 6, 7, 8, 9}},
      {LensModel::kPinholeEqui, "pinhole-equi", LensFamily::kEquidistant, {5, 6, 7, 8}},
  };
  return models;
}

LensFamily FamilyOf(LensModel model) {
  for (const LensModelInfo& info : LensModels()) {
    if (info.model == model) return info.family;
  }
  return LensFamily::kRadTan;
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
