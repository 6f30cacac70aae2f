// The omnidirectional lenses the lens-family tests use (unified, eucm, double sphere, with alpha
// on both sides of 1/2 and xi on both sides of 1), their tolerances, and the papers' models
// written with angles (independent of camera.h's algebra): tests/camera/lens_families_test.cc and
// lens_families_edge_test.cc.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "camera/camera.h"

namespace calibench {
namespace lens_test {

// Projection against an independent form: both sides are ~30 flops on pixel values up to ~2e3,
// so they agree to ~1e-12 px; a wrong term moves pixels by more than 1e-4 px for these lenses.
constexpr double kProjectionTolPx = 1e-10;
// ...on the points imaged within kMaxImageRadius (normalised, 4 f = 1420 px) of the centre, a
// sensor's reach: nearer a denominator's zero (alpha <= 1/2, xi <= 1) both forms lose digits as
// 1/den^2 (4e-10 px at 24 f for eucm alpha = 0.35).
constexpr double kMaxImageRadius = 4.0;
// Pixel -> ray -> pixel: closed-form lifts lose ~1e-15 relative; unified's radtan fixed point stops
// at a step below 1e-12 (normalised), which its contraction (< 0.3 here) keeps below 1e-12 * f.
constexpr double kPixelRoundTripTolPx = 1e-10;
// Ray -> pixel -> ray (unit rays): the inverse amplifies the pixel's 1e-13 rounding by the
// conditioning d(ray)/d(pixel) <= ~1/f * 10 near the edges tested (1 deg inside).
constexpr double kRayRoundTripTol = 1e-10;
// Central differences with h = 1e-6 relative: truncation ~h^2 = 1e-12 relative, rounding ~eps
// * |pixel| / h ~ 2e-7 px on pixels up to 1e3: 1e-6 relative (absolute below 1) covers both.
constexpr double kNumericJacobianRelTol = 1e-6;
// The region's edge located by bisection to 1e-12 rad; points 1e-6 rad either side of it.
constexpr double kEdgeStepRad = 1e-6;

constexpr double kDeg = M_PI / 180.0;

inline CameraIntrinsics Camera(LensFamily family) {
  CameraIntrinsics k;
  k.family = family;
  k.fku_px = 355.0, k.fkv_px = 352.5, k.phi_deg = 89.6, k.u0_px = 641.0, k.v0_px = 479.0;
  return k;
}
inline CameraIntrinsics Unified(double xi, double k1, double k2, double p1, double p2) {
  CameraIntrinsics k = Camera(LensFamily::kUnified);
  k.xi = xi, k.k1 = k1, k.k2 = k2, k.p1 = p1, k.p2 = p2;
  return k;
}
inline CameraIntrinsics Eucm(double alpha, double beta) {
  CameraIntrinsics k = Camera(LensFamily::kEucm);
  k.alpha = alpha, k.beta = beta;
  return k;
}
inline CameraIntrinsics DoubleSphere(double xi, double alpha) {
  CameraIntrinsics k = Camera(LensFamily::kDoubleSphere);
  k.xi = xi, k.alpha = alpha;
  return k;
}

// The lenses tested: each family with alpha on both sides of 1/2 and xi on both sides of 1.
inline std::vector<CameraIntrinsics> UnifiedLenses() {
  return {Unified(1.6, -0.08, 0.02, 4e-4, -3e-4),  // xi > 1: the sphere's rim at 128.7 deg.
          Unified(0.9, -0.02, 1e-3, 2e-4, 1e-4),   // 308 deg of sphere; radtan on it.
          Unified(0.6, 0.0, 0.0, 0.0, 0.0)};
}
inline std::vector<CameraIntrinsics> EucmLenses() {
  return {Eucm(0.5903, 1.1275),  // basalt's EuRoC calibration: alpha > 1/2, a fold.
          Eucm(0.6291, 1.0418),  // basalt's TUM VI 512.
          Eucm(0.35, 0.9)};      // alpha < 1/2: the denominator's edge.
}
inline std::vector<CameraIntrinsics> DoubleSphereLenses() {
  return {DoubleSphere(0.25, 0.6), DoubleSphere(0.6, 0.4), DoubleSphere(1.3, 0.55),
          DoubleSphere(-0.2, 0.6)};  // xi < 0, as real fisheyes fit (TUM VI: -0.19).
}
inline std::vector<CameraIntrinsics> AllLenses() {
  std::vector<CameraIntrinsics> all = UnifiedLenses();
  for (const auto& set : {EucmLenses(), DoubleSphereLenses()})
    all.insert(all.end(), set.begin(), set.end());
  return all;
}

// Prints a measured figure beside the test's verdict (the margin under each tolerance).
inline void Measured(const std::string& what, double value) {
  std::printf("[ measured ] %s: %.3g\n", what.c_str(), value);
}

inline std::string Name(const CameraIntrinsics& k) {
  std::string name = ToString(k.family);
  for (int i = 5; i < 10; ++i) {
    if (std::string(ParamNames(k.family)[i]) != "-") {
      name += " " + std::string(ParamNames(k.family)[i]) + "=" + std::to_string(k.Params()[i]);
    }
  }
  return name;
}

inline Eigen::Vector3d Ray(double theta, double azimuth) {
  return Eigen::Vector3d(std::sin(theta) * std::cos(azimuth), std::sin(theta) * std::sin(azimuth),
                         std::cos(theta));
}

// ---- The models written with angles (the papers' geometry, not camera.h's algebra) ----

// Image radius and denominator of the sphere part of each model for a ray at angle theta from
// the axis (the azimuth only turns the image): m = sin(.) / den, valid while den > 0 and m grows.
struct RadialImage {
  double m, den;
};

// Unified: the unit sphere seen from (0, 0, -xi).
inline RadialImage UnifiedRadial(double xi, double theta) {
  const double den = std::cos(theta) + xi;
  return {std::sin(theta) / den, den};
}
// Eucm: the ray scaled onto the ellipsoid beta (x^2 + y^2) + z^2 = 1 at angle psi there, seen as
// unified with xi = alpha / (1 - alpha) and its image shrunk by sqrt(beta).
inline RadialImage EucmRadial(double alpha, double beta, double theta) {
  const double psi = std::atan2(std::sqrt(beta) * std::sin(theta), std::cos(theta));
  const double den = std::sqrt(beta) * (alpha + (1 - alpha) * std::cos(psi));
  return {std::sin(psi) / den, den};
}
// Double sphere: the unit sphere's point moved by xi along the axis (second sphere's centre at
// -xi), its direction psi from there, then eucm with beta = 1.
inline RadialImage DoubleSphereRadial(double xi, double alpha, double theta) {
  const double psi = std::atan2(std::sin(theta), std::cos(theta) + xi);
  return EucmRadial(alpha, 1.0, psi);
}
inline RadialImage Radial(const CameraIntrinsics& k, double theta) {
  switch (k.family) {
    case LensFamily::kUnified:
      return UnifiedRadial(k.xi, theta);
    case LensFamily::kEucm:
      return EucmRadial(k.alpha, k.beta, theta);
    case LensFamily::kDoubleSphere:
      return DoubleSphereRadial(k.xi, k.alpha, theta);
    case LensFamily::kRadTan:  // Not used for these (the pinhole's image, for completeness).
    case LensFamily::kEquidistant:
      return {std::tan(theta), 1.0};
  }
  return {std::tan(theta), 1.0};
}

// Where the angle form stops being valid: the first theta with den <= 0 or dm/dtheta <= 0, found
// by a scan then bisection (independent of camera.h's closed-form edges).
inline double EdgeAngle(const CameraIntrinsics& k) {
  auto valid = [&](double theta) {
    const double h = 1e-7;
    const RadialImage a = Radial(k, theta - h), b = Radial(k, theta + h);
    return Radial(k, theta).den > 0 && a.den > 0 && b.den > 0 && b.m > a.m;
  };
  double lo = 0.01, hi = M_PI;
  for (double t = lo; t < M_PI; t += 1e-3) {
    if (!valid(t)) {
      hi = t;
      break;
    }
    lo = t;
  }
  while (hi - lo > 1e-12) (valid(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

// The pixel of the ray at (theta, azimuth) from the angle form: radtan for unified, then A.
inline Eigen::Vector2d AnglePixel(const CameraIntrinsics& k, double theta, double azimuth) {
  const double m = Radial(k, theta).m;
  double x = m * std::cos(azimuth), y = m * std::sin(azimuth);
  if (k.family == LensFamily::kUnified) {  // OpenCV's radtan, written out.
    const double r2 = x * x + y * y, d = 1 + k.k1 * r2 + k.k2 * r2 * r2;
    const double xd = x * d + 2 * k.p1 * x * y + k.p2 * (r2 + 2 * x * x);
    y = y * d + k.p1 * (r2 + 2 * y * y) + 2 * k.p2 * x * y;
    x = xd;
  }
  return (k.Matrix() * Eigen::Vector3d(x, y, 1)).head<2>();
}

}  // namespace lens_test
}  // namespace calibench
