// THE list of calibench's lens families: each family declared once, as a camera type (a small value
// type with `template <typename T> static bool Project(params, point_in_cam, pixel)` usable with
// ceres::Jet) whose `kInfo` row says everything the rest of the suite asks of a family: its name,
// the meaning of the raw lens slots 5..9, their valid ranges, whether its rays reach past 90 deg,
// how the renderer tabulates its rays, whether OpenCV (zhang) can start it, and what the camera
// files call it. The math of every family is in camera/camera.h's header comment; the inverse
// (UnprojectToRay) and the monotonicity test are in camera.cc, the analytic Jacobian in
// batch/projection_jacobian.cc, the wide start in batch/wide_init.cc: each an exhaustive switch
// over LensFamily, compiled with -Wswitch-enum, so a new family is a compile warning there until
// it has its case.
//
// Code that needs one family's behaviour dispatches once per batch of points:
//     VisitLensFamily(k.family, [&](auto camera) {
//       using Camera = decltype(camera);            // e.g. EucmCamera
//       for (...) Camera::Project(params, point, pixel);  // no switch per point
//     });
// Code that needs its facts reads InfoOf(family) or loops over LensFamilies() (names, ranges,
// file names): no list of families is written out anywhere else.
//
// Parameter order of the raw array (kNumParams = 10): the pinhole slots [fku_px, fkv_px, phi_rad,
// u0_px, v0_px] (focal lengths and principal point in pixels, phi in radians), then the family's
// lens slots kInfo.lens_params (unitless; "-": unused, kept at 0).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace calibench {

// How the five lens slots are read: one enumerator per camera type below (LensFamilies()).
enum class LensFamily { kRadTan, kEquidistant, kUnified, kEucm, kDoubleSphere };

// How the renderer tabulates a family's rays (sim/board_shader.h): on the plane z = 1, or in
// stereographic coordinates for a lens whose image reaches 90 deg from the axis (or past it).
enum class LensRaySpace { kPlane, kStereographic };

constexpr double kNoUpperBound = std::numeric_limits<double>::infinity();

// The valid range of one lens parameter: lower < value (lower_open) or lower <= value, and
// value <= upper. CameraIntrinsics::Check refuses values outside it ("xi must be >= 0 for the
// unified model"), the refinement bounds the parameter by it (an open end stays a margin inside).
struct LensParamRange {
  const char* name = nullptr;  // A lens slot's name; nullptr: no range in this row.
  double lower = 0.0;
  bool lower_open = false;
  double upper = kNoUpperBound;
  const char* note = "";  // Appended to Check's message, e.g. why the bound is there.
};

// What Kalibr's camchain YAML calls a family (Kalibr's kalibr_common/ConfigReader.py): the
// camera_model and the intrinsics before fu fv pu pv, and the distortion_model with its
// coefficients (the lens slots' names; Kalibr's radtan has no k3).
struct KalibrNames {
  const char* camera_model;
  std::array<const char*, 2> lens;  // nullptr: none.
  const char* distortion_model;
  std::array<const char*, 4> coefficients;  // nullptr: none.
};

struct LensFamilyInfo {
  LensFamily family;
  const char* name;                        // As configs, camera files and ToString() spell it.
  std::array<const char*, 5> lens_params;  // Names of the raw slots 5..9; "-" for unused.
  std::array<LensParamRange, 2> ranges;    // The lens parameters whose values are bounded.
  bool sees_past_90;  // Rays at Z <= 0 project: pinhole-based methods refuse the lens, the
                      // renderer's detector draws its photometric fit through the lens.
  LensRaySpace ray_space;
  bool zhang_starts;  // OpenCV's calibrateCamera / fisheye::calibrate can start it (batch/zhang).
  // Camera files (io/camera_io*): the OpenCV file's distortion_model is `name`;
  // `opencv_alias` is read as well (OpenCV's own name; nullptr: none).
  const char* opencv_alias;
  KalibrNames kalibr;
  bool mrcal_stores;     // mrcal 2.2 has a lens model for it (LENSMODEL_PINHOLE/OPENCV*).
  const char* known_as;  // The name in messages that refuse it (e.g. "unified (Mei)").
  // A typical lens of the family (slots 5..9) and the focal scale that keeps the image of a
  // 330 px pinhole about the same size: the list test's and the micro-benchmarks' camera.
  std::array<double, 5> example_lens;
  double example_focal_scale;
};

// pixel = A (xd, yd, 1): the pinhole slots 0..4 (fku, fkv, phi_rad, u0, v0) of every family.
template <typename T>
void ApplyIntrinsicMatrix(const T* params, const T& xd, const T& yd, T* pixel) {
  using std::cos;
  using std::sin;
  const T sin_phi = sin(params[2]);
  const T cos_phi = cos(params[2]);
  pixel[0] = params[0] * (xd - yd * cos_phi / sin_phi) + params[3];
  pixel[1] = params[1] * yd / sin_phi + params[4];
}

// OpenCV's radial-tangential distortion of normalised (x, y) (header comment): radtan and unified.
// xd, yd must not alias x, y.
template <typename T>
void ApplyRadTan(const T& k1, const T& k2, const T& p1, const T& p2, const T& k3, const T& x,
                 const T& y, T* xd, T* yd) {
  const T r2 = x * x + y * y;
  const T d = T(1) + r2 * (k1 + r2 * (k2 + r2 * k3));
  const T xy = x * y;
  *xd = d * x + T(2) * p1 * xy + p2 * (r2 + T(2) * x * x);
  *yd = d * y + p1 * (r2 + T(2) * y * y) + T(2) * p2 * xy;
}

// d(xd, yd) / d(x, y) of ApplyRadTan: the inverse's Newton step (camera.cc) and the refinement's
// analytic Jacobians (batch/projection_jacobian.cc).
inline Eigen::Matrix2d RadTanJacobian(double k1, double k2, double p1, double p2, double k3,
                                      double x, double y) {
  const double r2 = x * x + y * y;
  const double d = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double dd_dr2 = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2);
  const double cross = 2.0 * x * y * dd_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
  Eigen::Matrix2d j;
  j << d + 2.0 * x * x * dd_dr2 + 2.0 * p1 * y + 6.0 * p2 * x, cross,  //
      cross, d + 2.0 * y * y * dd_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
  return j;
}

struct PinholeSkewCamera {
  static constexpr int kNumParams = 10;
  static constexpr LensFamilyInfo kInfo = {LensFamily::kRadTan,
                                           "radtan",
                                           {"k1", "k2", "p1", "p2", "k3"},
                                           {},  // k1..k3, p1, p2: any finite value.
                                           /*sees_past_90=*/false,
                                           LensRaySpace::kPlane,
                                           /*zhang_starts=*/true,
                                           /*opencv_alias=*/"plumb_bob",
                                           {"pinhole", {}, "radtan", {"k1", "k2", "p1", "p2"}},
                                           /*mrcal_stores=*/true,
                                           /*known_as=*/"radtan (OpenCV)",
                                           {-0.25, 0.07, 2e-4, -1e-4, 0.0},
                                           1.0};

  // Projects point_in_cam (3 values) to pixel (2 values). Returns false, leaving pixel untouched,
  // when the point is not strictly in front of the camera (Z <= 0). Never throws.
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    if (!(point_in_cam[2] > T(0))) return false;
    const T x = point_in_cam[0] / point_in_cam[2];
    const T y = point_in_cam[1] / point_in_cam[2];
    T xd, yd;
    ApplyRadTan(params[5], params[6], params[7], params[8], params[9], x, y, &xd, &yd);
    ApplyIntrinsicMatrix(params, xd, yd, pixel);
    return true;
  }
};

// The equidistant (Kannala-Brandt) fisheye; same pinhole slots, distortion slots k1..k4.
struct PinholeEquiCamera {
  static constexpr int kNumParams = 10;
  static constexpr LensFamilyInfo kInfo = {
      LensFamily::kEquidistant,
      "equidistant",
      {"k1", "k2", "k3", "k4", "-"},
      {},  // k1..k4: any finite value.
      /*sees_past_90=*/false,
      LensRaySpace::kStereographic,  // Its image reaches 90 deg from the axis.
      /*zhang_starts=*/true,         // cv::fisheye.
      /*opencv_alias=*/"fisheye",
      {"pinhole", {}, "equidistant", {"k1", "k2", "k3", "k4"}},
      /*mrcal_stores=*/false,
      /*known_as=*/"Kannala-Brandt (equidistant)",
      {0.02, -0.01, 0.004, -8e-4, 0.0},
      1.0};

  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::atan;
    using std::sqrt;
    if (!(point_in_cam[2] > T(0))) return false;
    const T x = point_in_cam[0] / point_in_cam[2];
    const T y = point_in_cam[1] / point_in_cam[2];
    const T r2 = x * x + y * y;
    // theta_d / r; at r -> 0 it tends to 1 (and its derivatives in x, y to 0): sqrt would give the
    // Jet an infinite derivative there.
    T scale(1);
    if (r2 > T(1e-24)) {
      const T r = sqrt(r2);
      const T theta = atan(r);
      const T t2 = theta * theta;
      const T theta_d =
          theta * (T(1) + t2 * (params[5] + t2 * (params[6] + t2 * (params[7] + t2 * params[8]))));
      scale = theta_d / r;
    }
    ApplyIntrinsicMatrix(params, scale * x, scale * y, pixel);
    return true;
  }
};

// The omnidirectional cameras below return false, leaving pixel untouched, for a point outside
// their valid region (header comment; this includes parameters outside their ranges and the
// origin). Every square root taken for a valid point is of a positive number (finite Jets).

// w of the eucm edge Z > -w d for weight alpha (also the double sphere's w1); alpha in [0, 1].
template <typename T>
T EucmEdgeWeight(const T& alpha) {
  return alpha > T(0.5) ? (T(1) - alpha) / alpha : alpha / (T(1) - alpha);
}

// Mei's unified model with radtan (k1, k2, p1, p2) on the sphere's image.
struct UnifiedCamera {
  static constexpr int kNumParams = 10;
  static constexpr LensFamilyInfo kInfo = {LensFamily::kUnified,
                                           "unified",
                                           {"xi", "k1", "k2", "p1", "p2"},
                                           {{{"xi", 0.0, false, kNoUpperBound, ""}}},
                                           /*sees_past_90=*/true,
                                           LensRaySpace::kStereographic,
                                           /*zhang_starts=*/false,
                                           /*opencv_alias=*/"omnidir",
                                           {"omni", {"xi"}, "radtan", {"k1", "k2", "p1", "p2"}},
                                           /*mrcal_stores=*/false,
                                           /*known_as=*/"unified (Mei)",
                                           {0.9, -0.05, 0.01, 2e-4, -1e-4},
                                           1.9};  // gamma = f (1 + xi).

  template <typename T>
  static bool InRegion(const T& xi, const T& z, const T& rho) {
    const T w = xi > T(1) ? T(1) / xi : xi;
    return z > -w * rho;
  }
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::sqrt;
    const T &x = point_in_cam[0], &y = point_in_cam[1], &z = point_in_cam[2];
    const T rho = sqrt(x * x + y * y + z * z);
    if (!InRegion(params[5], z, rho)) return false;
    const T den = z + params[5] * rho;
    T xd, yd;
    ApplyRadTan(params[6], params[7], params[8], params[9], T(0), x / den, y / den, &xd, &yd);
    ApplyIntrinsicMatrix(params, xd, yd, pixel);
    return true;
  }
};

// The extended unified model (alpha, beta).
struct EucmCamera {
  static constexpr int kNumParams = 10;
  static constexpr LensFamilyInfo kInfo = {
      LensFamily::kEucm,
      "eucm",
      {"alpha", "beta", "-", "-", "-"},
      {{{"alpha", 0.0, false, 1.0, ""}, {"beta", 0.0, true, kNoUpperBound, ""}}},
      /*sees_past_90=*/true,
      LensRaySpace::kStereographic,
      /*zhang_starts=*/false,
      /*opencv_alias=*/nullptr,
      {"eucm", {"alpha", "beta"}, "none", {}},
      /*mrcal_stores=*/false,
      /*known_as=*/"eucm",
      {0.6, 1.1, 0.0, 0.0, 0.0},
      1.0};

  template <typename T>
  static bool InRegion(const T& alpha, const T& beta, const T& z, const T& d) {
    if (!(alpha >= T(0) && alpha <= T(1) && beta > T(0))) return false;
    return z > -EucmEdgeWeight(alpha) * d;
  }
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::sqrt;
    const T &x = point_in_cam[0], &y = point_in_cam[1], &z = point_in_cam[2];
    const T &alpha = params[5], &beta = params[6];
    const T d = sqrt(beta * (x * x + y * y) + z * z);
    if (!InRegion(alpha, beta, z, d)) return false;
    const T den = alpha * d + (T(1) - alpha) * z;
    ApplyIntrinsicMatrix(params, x / den, y / den, pixel);
    return true;
  }
};

// The double sphere model (xi, alpha).
struct DoubleSphereCamera {
  static constexpr int kNumParams = 10;
  static constexpr LensFamilyInfo kInfo = {
      LensFamily::kDoubleSphere,
      "double-sphere",
      {"xi", "alpha", "-", "-", "-"},
      {{{"xi", -1.0, true, kNoUpperBound, " (the second sphere's centre inside the first)"},
        {"alpha", 0.0, false, 1.0, ""}}},
      /*sees_past_90=*/true,
      LensRaySpace::kStereographic,
      /*zhang_starts=*/false,
      /*opencv_alias=*/nullptr,
      {"ds", {"xi", "alpha"}, "none", {}},
      /*mrcal_stores=*/false,
      /*known_as=*/"double-sphere",
      {-0.2, 0.6, 0.0, 0.0, 0.0},
      0.8};  // f (1 + xi) on the axis.

  template <typename T>
  static bool InRegion(const T& xi, const T& alpha, const T& z, const T& d1) {
    using std::sqrt;
    if (!(alpha >= T(0) && alpha <= T(1))) return false;
    const T w1 = EucmEdgeWeight(alpha), u = T(1) - w1 * w1;
    const T w2 = xi > T(1) ? T(1) / xi : xi * u + w1 * sqrt(T(1) - xi * xi * u);
    return z > -w2 * d1;
  }
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::sqrt;
    const T &x = point_in_cam[0], &y = point_in_cam[1], &z = point_in_cam[2];
    const T &xi = params[5], &alpha = params[6];
    const T r2 = x * x + y * y;
    const T d1 = sqrt(r2 + z * z);
    if (!InRegion(xi, alpha, z, d1)) return false;
    const T k = xi * d1 + z;
    const T den = alpha * sqrt(r2 + k * k) + (T(1) - alpha) * k;
    ApplyIntrinsicMatrix(params, x / den, y / den, pixel);
    return true;
  }
};

// Calls visit(Camera{}) with `family`'s camera type: the one switch over the families, taken once
// per batch (the visitor runs the templated code for every point).
template <typename Visitor>
decltype(auto) VisitLensFamily(LensFamily family, Visitor&& visit) {
  switch (family) {
    case LensFamily::kRadTan:
      return visit(PinholeSkewCamera{});
    case LensFamily::kEquidistant:
      return visit(PinholeEquiCamera{});
    case LensFamily::kUnified:
      return visit(UnifiedCamera{});
    case LensFamily::kEucm:
      return visit(EucmCamera{});
    case LensFamily::kDoubleSphere:
      return visit(DoubleSphereCamera{});
  }
  throw std::invalid_argument("VisitLensFamily: not a LensFamily enumerator");
}

// Every family's row, in enumerator order (the order of configs' and docs' lists).
inline constexpr std::array<LensFamilyInfo, 5> kLensFamilies = {
    PinholeSkewCamera::kInfo, PinholeEquiCamera::kInfo, UnifiedCamera::kInfo, EucmCamera::kInfo,
    DoubleSphereCamera::kInfo};
inline const std::array<LensFamilyInfo, 5>& LensFamilies() { return kLensFamilies; }
constexpr bool LensFamiliesInEnumeratorOrder() {
  for (size_t i = 0; i < kLensFamilies.size(); ++i) {
    if (kLensFamilies[i].family != static_cast<LensFamily>(i)) return false;
  }
  return true;
}
static_assert(LensFamiliesInEnumeratorOrder(), "kLensFamilies[i] must be LensFamily(i)'s row");
// True for every enumerator: -Wswitch-enum makes a new one add its case here, and then the
// static_assert below fails until kLensFamilies has its row (InfoOf would index past the end).
constexpr bool IsLensFamily(LensFamily family) {
  switch (family) {
    case LensFamily::kRadTan:
    case LensFamily::kEquidistant:
    case LensFamily::kUnified:
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere:
      return true;
  }
  return false;
}
static_assert(!IsLensFamily(static_cast<LensFamily>(kLensFamilies.size())),
              "every LensFamily enumerator needs its row in kLensFamilies");

// The row of `family`.
inline const LensFamilyInfo& InfoOf(LensFamily family) {
  return kLensFamilies[static_cast<size_t>(family)];
}

// Project<T> of `family`'s camera type. Per point: in a loop, VisitLensFamily once instead.
template <typename T>
bool ProjectLens(LensFamily family, const T* params, const T* point_in_cam, T* pixel) {
  return VisitLensFamily(
      family, [&](auto camera) { return decltype(camera)::Project(params, point_in_cam, pixel); });
}

}  // namespace calibench
