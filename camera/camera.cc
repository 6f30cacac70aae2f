#include "camera/camera.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace calibench {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// A lens field and its neutral value (what a family without it must hold).
struct LensFieldRow {
  const char* name;  // As ParamNames() spells it.
  double CameraIntrinsics::*member;
  double neutral;
};
constexpr LensFieldRow kLensFields[] = {
    {"k1", &CameraIntrinsics::k1, 0},    {"k2", &CameraIntrinsics::k2, 0},
    {"p1", &CameraIntrinsics::p1, 0},    {"p2", &CameraIntrinsics::p2, 0},
    {"k3", &CameraIntrinsics::k3, 0},    {"k4", &CameraIntrinsics::k4, 0},
    {"xi", &CameraIntrinsics::xi, 0},    {"alpha", &CameraIntrinsics::alpha, 0},
    {"beta", &CameraIntrinsics::beta, 1}};

// The family's own lens fields, as its slots 5..9 name them (ParamNames).
bool FamilyHas(LensFamily family, const char* name) {
  const auto& names = ParamNames(family);
  return std::any_of(names.begin() + 5, names.end(),
                     [&](const char* n) { return std::string(n) == name; });
}

std::string FamilyFieldList(LensFamily family) {
  std::string list;
  for (int i = 5; i < 10; ++i) {
    const std::string name = ParamNames(family)[i];
    if (name != "-") list += (list.empty() ? "" : ", ") + name;
  }
  return list;
}

// A field k's family lacks, away from its neutral value: named with the family's own fields.
std::string ForeignFieldProblem(const CameraIntrinsics& k) {
  std::ostringstream msg;
  for (const LensFieldRow& f : kLensFields) {
    if (k.*f.member == f.neutral || FamilyHas(k.family, f.name)) continue;
    msg << f.name << " is not a parameter of the " << ToString(k.family) << " model (it has "
        << FamilyFieldList(k.family) << "): " << f.name << " must be " << f.neutral << ", got "
        << k.*f.member;
    break;
  }
  return msg.str();
}

// A lens parameter outside its family's range (LensFamilyInfo::ranges); empty if none.
std::string RangeProblem(const CameraIntrinsics& k) {
  std::ostringstream msg;
  const LensFamilyInfo& info = InfoOf(k.family);
  for (const LensParamRange& range : info.ranges) {
    if (range.name == nullptr) continue;
    const double value = *LensField(k, range.name);
    const bool above = range.lower_open ? value > range.lower : value >= range.lower;
    if (above && value <= range.upper) continue;
    msg << range.name << " must ";
    if (range.upper != kNoUpperBound) {
      msg << "lie in [" << range.lower << ", " << range.upper << "]";
    } else {
      msg << (range.lower_open ? "be > " : "be >= ") << range.lower;
    }
    msg << " for the " << info.name << " model" << range.note << ", got " << value;
    break;
  }
  return msg.str();
}

// The lens fields' problem for k's family; empty if none.
std::string LensFieldProblem(const CameraIntrinsics& k) {
  std::ostringstream msg;
  for (const LensFieldRow& f : kLensFields) {
    if (!std::isfinite(k.*f.member)) {
      msg << "lens field " << f.name << " must be finite, got " << k.*f.member;
      return msg.str();
    }
  }
  if (k.family == LensFamily::kRadTan && k.k4 != 0) {
    msg << "k4 belongs to the equidistant (fisheye) family; the radtan model has k1, k2, p1, p2, "
           "k3 (got k4 "
        << k.k4 << ")";
    return msg.str();
  }
  if (k.family == LensFamily::kEquidistant && (k.p1 != 0 || k.p2 != 0)) {
    msg << "the equidistant (fisheye) model has k1..k4 and no tangential terms (got p1 " << k.p1
        << ", p2 " << k.p2 << ")";
    return msg.str();
  }
  const std::string foreign = ForeignFieldProblem(k);
  return foreign.empty() ? RangeProblem(k) : foreign;
}

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
  } else {
    msg << LensFieldProblem(*this);
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

namespace {

// d/dr [r (1 + k1 r^2 + k2 r^4 + k3 r^6)] at r2 = r^2: the radial slope of radtan.
double RadTanRadialSlope(double k1, double k2, double k3, double r2) {
  return 1 + r2 * (3 * k1 + r2 * (5 * k2 + r2 * 7 * k3));
}

}  // namespace

bool CameraIntrinsics::DistortionIsMonotoneAt(double r2) const {
  switch (family) {
    case LensFamily::kRadTan:
      return RadTanRadialSlope(k1, k2, k3, r2) > 0;
    case LensFamily::kEquidistant: {  // d/dtheta [theta (1 + k1 t^2 + .. + k4 t^8)], t = theta.
      const double theta = std::atan(std::sqrt(r2)), t2 = theta * theta;
      return 1 + t2 * (3 * k1 + t2 * (5 * k2 + t2 * (7 * k3 + t2 * 9 * k4))) > 0;
    }
    case LensFamily::kUnified:
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere: {
      // The sphere (ellipsoid) steps are one-to-one inside the region; unified's radtan acts at
      // the sphere image's radius m = r / (1 + xi sqrt(1 + r^2)) (X = r, Z = 1).
      Eigen::Vector2d pixel;
      const double r = std::sqrt(r2);
      if (!ProjectPoint(*this, Eigen::Vector3d(r, 0, 1), &pixel)) return false;
      if (family != LensFamily::kUnified) return true;
      const double m = r / (1 + xi * std::sqrt(1 + r2));
      return RadTanRadialSlope(k1, k2, 0, m * m) > 0;
    }
  }
  throw std::invalid_argument("DistortionIsMonotoneAt: not a LensFamily enumerator");
}

bool CameraIntrinsics::DistortionIsMonotoneAlong(const Eigen::Vector3d& p) const {
  const double r2 = p.x() * p.x() + p.y() * p.y();
  switch (family) {
    case LensFamily::kRadTan:
    case LensFamily::kEquidistant:
      return p.z() > 0 && DistortionIsMonotoneAt(r2 / (p.z() * p.z()));
    case LensFamily::kUnified:
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere: {
      Eigen::Vector2d pixel;
      if (!ProjectPoint(*this, p, &pixel)) return false;
      if (family != LensFamily::kUnified) return true;
      const double den = p.z() + xi * p.norm();  // > 0 inside the region; m = |(X, Y)| / den.
      return RadTanRadialSlope(k1, k2, 0, r2 / (den * den)) > 0;
    }
  }
  throw std::invalid_argument("DistortionIsMonotoneAlong: not a LensFamily enumerator");
}

std::array<double, 10> CameraIntrinsics::Params() const {
  const double phi = phi_deg * kDegToRad;
  std::array<double, 10> params = {fku_px, fkv_px, phi, u0_px, v0_px, 0, 0, 0, 0, 0};
  // Every field the family has, into the slot its LensFamilyInfo::lens_params gives it.
  const auto& names = InfoOf(family).lens_params;
  for (int i = 0; i < 5; ++i) {
    if (const double* field = LensField(*this, names[i])) params[5 + i] = *field;
  }
  return params;
}

CameraIntrinsics CameraIntrinsics::FromParams(const double* params, LensFamily family) {
  CameraIntrinsics k;
  k.family = family;
  k.fku_px = params[0];
  k.fkv_px = params[1];
  k.phi_deg = params[2] / kDegToRad;
  k.u0_px = params[3];
  k.v0_px = params[4];
  // Every field the family has, from the slot its LensFamilyInfo::lens_params gives it.
  const auto& names = InfoOf(family).lens_params;
  for (int i = 0; i < 5; ++i) {
    if (double* field = LensField(&k, names[i])) *field = params[5 + i];
  }
  return k;
}

const char* ToString(LensFamily family) { return InfoOf(family).name; }

const std::array<const char*, 10>& ParamNames(LensFamily family) {
  static const auto names = [] {
    std::array<std::array<const char*, 10>, kLensFamilies.size()> all;
    for (size_t f = 0; f < kLensFamilies.size(); ++f) {
      all[f] = {"fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px"};
      for (int i = 0; i < 5; ++i) all[f][5 + i] = kLensFamilies[f].lens_params[i];
    }
    return all;
  }();
  return names[static_cast<size_t>(family)];
}

const double* LensField(const CameraIntrinsics& k, const std::string& name) {
  for (const LensFieldRow& f : kLensFields) {
    if (name == f.name) return &(k.*f.member);
  }
  return nullptr;
}

double* LensField(CameraIntrinsics* k, const std::string& name) {
  return const_cast<double*>(LensField(*k, name));
}

bool ProjectPoint(const CameraIntrinsics& intrinsics, const Eigen::Vector3d& point_in_cam,
                  Eigen::Vector2d* pixel) {
  const std::array<double, 10> params = intrinsics.Params();
  return ProjectLens(intrinsics.family, params.data(), point_in_cam.data(), pixel->data());
}

namespace {

// ApplyRadTan of p (camera.h) minus `target`, and the distortion's Jacobian at p.
struct RadTanAt {
  Eigen::Vector2d residual;
  Eigen::Matrix2d jacobian;
};
RadTanAt EvaluateRadTan(double k1, double k2, double p1, double p2, double k3,
                        const Eigen::Vector2d& p, const Eigen::Vector2d& target) {
  RadTanAt at;
  ApplyRadTan(k1, k2, p1, p2, k3, p.x(), p.y(), &at.residual.x(), &at.residual.y());
  at.residual -= target;
  at.jacobian = RadTanJacobian(k1, k2, p1, p2, k3, p.x(), p.y());
  return at;
}

// radtan^-1: the (x, y) whose radtan (k1, k2, p1, p2, k3) is `distorted`. Fixed-point iteration to
// 1e-12; where it stops contracting (far out on a sphere's image: unified's radtan grows without
// bound) damped Newton to 1e-12 of the image radius. Refused past a fold (the Jacobian's
// determinant <= 0 at the solution: another, nearer point has the same image).
bool InvertRadTan(double k1, double k2, double p1, double p2, double k3,
                  const Eigen::Vector2d& distorted, Eigen::Vector2d* undistorted) {
  Eigen::Vector2d p = distorted;
  for (int it = 0; it < 100; ++it) {
    const double x = p.x(), y = p.y(), r2 = x * x + y * y;
    const double d = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dx = 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    const double dy = p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    const Eigen::Vector2d next((distorted.x() - dx) / d, (distorted.y() - dy) / d);
    if (!next.allFinite() || d <= 0) break;
    const double change = (next - p).norm();
    p = next;
    if (change < 1e-12) {
      *undistorted = p;
      return true;
    }
  }
  const double tolerance = 1e-12 * std::max(1.0, distorted.norm());
  p = distorted;
  RadTanAt at = EvaluateRadTan(k1, k2, p1, p2, k3, p, distorted);
  for (int it = 0; it < 100; ++it) {
    if (!(at.jacobian.determinant() > 0)) return false;  // A fold on the way (or at p).
    const Eigen::Vector2d step = -at.jacobian.inverse() * at.residual;
    double scale = 1.0;
    RadTanAt next;
    for (;; scale *= 0.5) {
      if (scale < 1e-6) return false;
      next = EvaluateRadTan(k1, k2, p1, p2, k3, p + scale * step, distorted);
      if (next.residual.norm() < at.residual.norm() || next.residual.norm() <= tolerance) break;
    }
    p += scale * step;
    at = next;
    if (at.residual.norm() <= tolerance && scale * step.norm() < 1e-12 * std::max(1.0, p.norm())) {
      if (!(at.jacobian.determinant() > 0)) return false;
      *undistorted = p;
      return true;
    }
  }
  return false;
}

// Equidistant^-1: theta_d = |distorted|; solve theta (1 + k1 t^2 + .. + k4 t^8) = theta_d for
// theta in [0, pi/2) by Newton from theta = theta_d; (x, y) = tan(theta) / theta_d * distorted.
bool InvertEquidistant(const CameraIntrinsics& k, const Eigen::Vector2d& distorted,
                       Eigen::Vector2d* undistorted) {
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

// Mei's lift of the sphere's image m onto the unit sphere; xi > 1 refuses r2 > 1/(xi^2 - 1).
bool LiftUnified(double xi, const Eigen::Vector2d& m, Eigen::Vector3d* ray) {
  const double r2 = m.squaredNorm(), s = 1 + (1 - xi * xi) * r2;
  if (!(s >= 0)) return false;
  const double f = (xi + std::sqrt(s)) / (1 + r2);
  *ray = Eigen::Vector3d(f * m.x(), f * m.y(), f - xi);
  return true;
}

// The eucm lift's third coordinate mz (ray ~ (m, mz)); alpha > 1/2 refuses r2 >= 1/(beta (2
// alpha - 1)), the fold.
bool EucmDepth(double alpha, double beta, double r2, double* mz) {
  const double s = 1 - (2 * alpha - 1) * beta * r2;
  if (!(s > 0)) return false;
  *mz = (1 - beta * alpha * alpha * r2) / (alpha * std::sqrt(s) + 1 - alpha);
  return true;
}

// The double sphere's lift: the eucm lift (beta = 1) from the second sphere's centre, back onto
// the first sphere; with xi > 1 that line must meet it, in front of the second centre.
bool LiftDoubleSphere(double xi, double alpha, const Eigen::Vector2d& m, Eigen::Vector3d* ray) {
  const double r2 = m.squaredNorm();
  double mz = 0;
  if (!EucmDepth(alpha, 1.0, r2, &mz)) return false;
  const double s = mz * mz + (1 - xi * xi) * r2;
  if (!(s >= 0)) return false;
  const double f = (mz * xi + std::sqrt(s)) / (mz * mz + r2);
  if (!(f > 0)) return false;
  *ray = Eigen::Vector3d(f * m.x(), f * m.y(), f * mz - xi);
  return true;
}

}  // namespace

// Every family's inverse (camera.h).
bool RayOfDistorted(const CameraIntrinsics& k, const Eigen::Vector2d& distorted,
                    Eigen::Vector3d* ray) {
  Eigen::Vector2d m;
  bool ok = false;
  switch (k.family) {
    case LensFamily::kRadTan:
      ok = InvertRadTan(k.k1, k.k2, k.p1, k.p2, k.k3, distorted, &m);
      *ray = m.homogeneous();
      break;
    case LensFamily::kEquidistant:
      ok = InvertEquidistant(k, distorted, &m);
      *ray = m.homogeneous();
      break;
    case LensFamily::kUnified:
      ok = InvertRadTan(k.k1, k.k2, k.p1, k.p2, 0.0, distorted, &m) && LiftUnified(k.xi, m, ray);
      break;
    case LensFamily::kEucm: {
      double mz = 0;
      ok = EucmDepth(k.alpha, k.beta, distorted.squaredNorm(), &mz);
      *ray = Eigen::Vector3d(distorted.x(), distorted.y(), mz);
      break;
    }
    case LensFamily::kDoubleSphere:
      ok = LiftDoubleSphere(k.xi, k.alpha, distorted, ray);
      break;
  }
  if (!ok || !ray->allFinite()) return false;
  ray->normalize();
  return true;
}

namespace {

Eigen::Vector2d DistortedOfPixel(const CameraIntrinsics& k, const Eigen::Vector2d& pixel) {
  return (k.Matrix().inverse() * pixel.homogeneous()).hnormalized();
}

}  // namespace

bool UnprojectToRay(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel,
                    Eigen::Vector3d* ray_in_cam) {
  return RayOfDistorted(intrinsics, DistortedOfPixel(intrinsics, pixel), ray_in_cam);
}

bool UnprojectPixel(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel,
                    Eigen::Vector2d* normalized) {
  return UndistortNormalized(intrinsics, DistortedOfPixel(intrinsics, pixel), normalized);
}

bool UndistortNormalized(const CameraIntrinsics& k, const Eigen::Vector2d& distorted,
                         Eigen::Vector2d* undistorted) {
  switch (k.family) {
    case LensFamily::kRadTan:
      return InvertRadTan(k.k1, k.k2, k.p1, k.p2, k.k3, distorted, undistorted);
    case LensFamily::kEquidistant:
      return InvertEquidistant(k, distorted, undistorted);
    case LensFamily::kUnified:
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere: {
      Eigen::Vector3d ray;
      if (!RayOfDistorted(k, distorted, &ray) || !(ray.z() > 0)) return false;
      *undistorted = ray.hnormalized();
      return true;
    }
  }
  throw std::invalid_argument("UndistortNormalized: not a LensFamily enumerator");
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
      {LensModel::kUnified, "unified", LensFamily::kUnified, {5, 6, 7, 8, 9}},
      {LensModel::kEucm, "eucm", LensFamily::kEucm, {5, 6}},
      {LensModel::kDoubleSphere, "double-sphere", LensFamily::kDoubleSphere, {5, 6}},
  };
  return models;
}

LensFamily FamilyOf(LensModel model) {
  for (const LensModelInfo& info : LensModels()) {
    if (info.model == model) return info.family;
  }
  throw std::invalid_argument("FamilyOf: a LensModel without a row in LensModels()");
}

LensModel FullModelOf(LensFamily family) {
  LensModel best = LensModel::kPinhole;
  size_t most = 0;
  for (const LensModelInfo& info : LensModels()) {
    if (info.family == family && info.free_distortion.size() >= most) {
      best = info.model;
      most = info.free_distortion.size();
    }
  }
  return best;
}

const char* ToString(LensModel model) {
  for (const LensModelInfo& info : LensModels()) {
    if (info.model == model) return info.name;
  }
  throw std::invalid_argument("ToString: a LensModel without a row in LensModels()");
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
