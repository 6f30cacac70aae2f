// The omnidirectional lens families of camera/camera.h (unified, eucm, double-sphere): projection
// against OpenCV's cv::omnidir and against the papers' models written with angles, Jet
// derivatives, round trips through UnprojectToRay out to each model's edge, the edge itself, and
// Check()'s refusals.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <opencv2/ccalib/omnidir.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "camera/camera.h"

namespace calibench {
namespace {

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

CameraIntrinsics Camera(LensFamily family) {
  CameraIntrinsics k;
  k.family = family;
  k.fku_px = 355.0, k.fkv_px = 352.5, k.phi_deg = 89.6, k.u0_px = 641.0, k.v0_px = 479.0;
  return k;
}
CameraIntrinsics Unified(double xi, double k1, double k2, double p1, double p2) {
  CameraIntrinsics k = Camera(LensFamily::kUnified);
  k.xi = xi, k.k1 = k1, k.k2 = k2, k.p1 = p1, k.p2 = p2;
  return k;
}
CameraIntrinsics Eucm(double alpha, double beta) {
  CameraIntrinsics k = Camera(LensFamily::kEucm);
  k.alpha = alpha, k.beta = beta;
  return k;
}
CameraIntrinsics DoubleSphere(double xi, double alpha) {
  CameraIntrinsics k = Camera(LensFamily::kDoubleSphere);
  k.xi = xi, k.alpha = alpha;
  return k;
}

// The lenses tested: each family with alpha on both sides of 1/2 and xi on both sides of 1.
std::vector<CameraIntrinsics> UnifiedLenses() {
  return {Unified(1.6, -0.08, 0.02, 4e-4, -3e-4),  // xi > 1: the sphere's rim at 128.7 deg.
          Unified(0.9, -0.02, 1e-3, 2e-4, 1e-4),   // 308 deg of sphere; radtan on it.
          Unified(0.6, 0.0, 0.0, 0.0, 0.0)};
}
std::vector<CameraIntrinsics> EucmLenses() {
  return {Eucm(0.5903, 1.1275),  // basalt's EuRoC calibration: alpha > 1/2, a fold.
          Eucm(0.6291, 1.0418),  // basalt's TUM VI 512.
          Eucm(0.35, 0.9)};      // alpha < 1/2: the denominator's edge.
}
std::vector<CameraIntrinsics> DoubleSphereLenses() {
  return {DoubleSphere(0.25, 0.6), DoubleSphere(0.6, 0.4), DoubleSphere(1.3, 0.55),
          DoubleSphere(-0.2, 0.6)};  // xi < 0, as real fisheyes fit (TUM VI: -0.19).
}
std::vector<CameraIntrinsics> AllLenses() {
  std::vector<CameraIntrinsics> all = UnifiedLenses();
  for (const auto& set : {EucmLenses(), DoubleSphereLenses()})
    all.insert(all.end(), set.begin(), set.end());
  return all;
}

// Prints a measured figure beside the test's verdict (the margin under each tolerance).
void Measured(const std::string& what, double value) {
  std::printf("[ measured ] %s: %.3g\n", what.c_str(), value);
}

std::string Name(const CameraIntrinsics& k) {
  std::string name = ToString(k.family);
  for (int i = 5; i < 10; ++i) {
    if (std::string(ParamNames(k.family)[i]) != "-") {
      name += " " + std::string(ParamNames(k.family)[i]) + "=" + std::to_string(k.Params()[i]);
    }
  }
  return name;
}

Eigen::Vector3d Ray(double theta, double azimuth) {
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
RadialImage UnifiedRadial(double xi, double theta) {
  const double den = std::cos(theta) + xi;
  return {std::sin(theta) / den, den};
}
// Eucm: the ray scaled onto the ellipsoid beta (x^2 + y^2) + z^2 = 1 at angle psi there, seen as
// unified with xi = alpha / (1 - alpha) and its image shrunk by sqrt(beta).
RadialImage EucmRadial(double alpha, double beta, double theta) {
  const double psi = std::atan2(std::sqrt(beta) * std::sin(theta), std::cos(theta));
  const double den = std::sqrt(beta) * (alpha + (1 - alpha) * std::cos(psi));
  return {std::sin(psi) / den, den};
}
// Double sphere: the unit sphere's point moved by xi along the axis (second sphere's centre at
// -xi), its direction psi from there, then eucm with beta = 1.
RadialImage DoubleSphereRadial(double xi, double alpha, double theta) {
  const double psi = std::atan2(std::sin(theta), std::cos(theta) + xi);
  return EucmRadial(alpha, 1.0, psi);
}
RadialImage Radial(const CameraIntrinsics& k, double theta) {
  switch (k.family) {
    case LensFamily::kUnified:
      return UnifiedRadial(k.xi, theta);
    case LensFamily::kEucm:
      return EucmRadial(k.alpha, k.beta, theta);
    case LensFamily::kDoubleSphere:
      return DoubleSphereRadial(k.xi, k.alpha, theta);
    default:
      return {std::tan(theta), 1.0};
  }
}

// Where the angle form stops being valid: the first theta with den <= 0 or dm/dtheta <= 0, found
// by a scan then bisection (independent of camera.h's closed-form edges).
double EdgeAngle(const CameraIntrinsics& k) {
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
Eigen::Vector2d AnglePixel(const CameraIntrinsics& k, double theta, double azimuth) {
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

// ---- Projection ----

// Mutations caught: the sign of xi in the denominator (Z - xi rho); p2's 2x^2 term dropped from
// the shared radtan.
TEST(UnifiedCamera, ProjectionEqualsOpenCvOmnidirOutToTheEdge) {
  for (const CameraIntrinsics& k : UnifiedLenses()) {
    const double edge = EdgeAngle(k);
    std::vector<cv::Vec3d> points;
    for (double theta = 0; theta < edge - 1 * kDeg; theta += 4 * kDeg) {
      if (Radial(k, theta).m > kMaxImageRadius) break;
      for (double azimuth = 0.1; azimuth < 2 * M_PI; azimuth += 0.6) {
        const Eigen::Vector3d p = 2.7 * Ray(theta, azimuth);
        points.emplace_back(p.x(), p.y(), p.z());
      }
    }
    std::vector<cv::Vec2d> expected;
    cv::Matx33d a;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) a(r, c) = k.Matrix()(r, c);
    }
    cv::omnidir::projectPoints(points, expected, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), a, k.xi,
                               cv::Vec4d(k.k1, k.k2, k.p1, k.p2));
    double max_err = 0;
    int wide = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      Eigen::Vector2d pixel;
      const Eigen::Vector3d p(points[i][0], points[i][1], points[i][2]);
      ASSERT_TRUE(ProjectPoint(k, p, &pixel)) << Name(k);
      max_err = std::max(max_err, (pixel - Eigen::Vector2d(expected[i][0], expected[i][1])).norm());
      wide += p.z() < 0;
    }
    EXPECT_LT(max_err, kProjectionTolPx) << Name(k);
    EXPECT_GT(wide, 0) << Name(k) << ": no point past 90 deg";
    Measured("omnidir " + Name(k) + " max px", max_err);
  }
}

// Mutations caught: alpha and (1 - alpha) swapped in the eucm denominator; beta dropped from d;
// the double sphere's denominator with d1 in place of d2; basalt's w2 (refuses points inside).
TEST(OmnidirectionalCameras, EucmAndDoubleSphereEqualTheAngleFormOutToTheEdge) {
  for (const auto& lenses : {EucmLenses(), DoubleSphereLenses()}) {
    for (const CameraIntrinsics& k : lenses) {
      const double edge = EdgeAngle(k);
      double max_err = 0, widest = 0;
      for (double theta = 0; theta < edge - 0.5 * kDeg; theta += 3 * kDeg) {
        if (Radial(k, theta).m > kMaxImageRadius) break;
        widest = theta;
        for (double azimuth = 0.1; azimuth < 2 * M_PI; azimuth += 0.6) {
          Eigen::Vector2d pixel;
          ASSERT_TRUE(ProjectPoint(k, 1.9 * Ray(theta, azimuth), &pixel))
              << Name(k) << " " << theta;
          max_err = std::max(max_err, (pixel - AnglePixel(k, theta, azimuth)).norm());
        }
      }
      EXPECT_LT(max_err, kProjectionTolPx) << Name(k);
      EXPECT_GT(widest, 95 * kDeg) << Name(k);
      Measured("angle form " + Name(k) + " max px", max_err);
    }
  }
}

// Special cases that reduce to the older models: unified with xi = 0 is radtan with k3 = 0, eucm
// with alpha = 0 and the double sphere with xi = alpha = 0 are the pinhole, the double sphere with
// alpha = 0 is unified without distortion. Mutations caught: Z - xi rho; eucm's alpha swapped.
TEST(OmnidirectionalCameras, ReduceToTheOlderModels) {
  CameraIntrinsics radtan = Camera(LensFamily::kRadTan);
  radtan.k1 = -0.2, radtan.k2 = 0.05, radtan.p1 = 1e-3, radtan.p2 = -2e-3;
  CameraIntrinsics unified0 = Unified(0.0, radtan.k1, radtan.k2, radtan.p1, radtan.p2);
  const CameraIntrinsics pinhole = Camera(LensFamily::kRadTan);
  const struct {
    CameraIntrinsics k, reference;
  } cases[] = {{unified0, radtan},
               {Eucm(0.0, 1.7), pinhole},
               {DoubleSphere(0.0, 0.0), pinhole},
               {DoubleSphere(0.7, 0.0), Unified(0.7, 0, 0, 0, 0)}};
  for (const auto& c : cases) {
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, -0.2, 1.0),
                                     Eigen::Vector3d(-1.1, 0.4, 0.8), Eigen::Vector3d(0, 0, 2)}) {
      Eigen::Vector2d a, b;
      ASSERT_TRUE(ProjectPoint(c.k, p, &a) && ProjectPoint(c.reference, p, &b)) << Name(c.k);
      EXPECT_LT((a - b).norm(), kProjectionTolPx) << Name(c.k);
    }
  }
}

// ---- Jet derivatives ----

// Includes points on the axis and past 90 deg. Mutation caught (values unchanged, so only here):
// unified's rho as sqrt(sqrt(X^2 + Y^2)^2 + Z^2), whose inner sqrt(0) on the axis makes the Jet
// NaN.
TEST(OmnidirectionalCameras, JetDerivativesMatchNumericDifferentiation) {
  using Jet = ceres::Jet<double, 13>;  // 10 parameters + 3 point coordinates.
  for (const CameraIntrinsics& k : AllLenses()) {
    const double edge = EdgeAngle(k);
    const std::vector<Eigen::Vector3d> points = {Eigen::Vector3d(0, 0, 1.5), 2.0 * Ray(0.4, 1.0),
                                                 1.3 * Ray(0.5 * edge, 2.5),
                                                 1.1 * Ray(edge - 3 * kDeg, -0.7)};
    for (const Eigen::Vector3d& point : points) {
      const auto params = k.Params();
      Jet jp[10], jx[3], jpix[2];
      for (int i = 0; i < 10; ++i) jp[i] = Jet(params[i], i);
      for (int i = 0; i < 3; ++i) jx[i] = Jet(point[i], 10 + i);
      ASSERT_TRUE(ProjectLens(k.family, jp, jx, jpix)) << Name(k);
      auto eval = [&](int var, double delta) {
        std::array<double, 10> p = params;
        Eigen::Vector3d x = point;
        (var < 10 ? p[var] : x[var - 10]) += delta;
        Eigen::Vector2d out(NAN, NAN);
        ProjectLens(k.family, p.data(), x.data(), out.data());
        return out;
      };
      for (int var = 0; var < 13; ++var) {
        const double h = 1e-6 * std::max(1.0, std::abs(var < 10 ? params[var] : point[var - 10]));
        const Eigen::Vector2d numeric = (eval(var, h) - eval(var, -h)) / (2 * h);
        for (int r = 0; r < 2; ++r) {
          ASSERT_TRUE(std::isfinite(jpix[r].v[var])) << Name(k) << " variable " << var;
          EXPECT_NEAR(jpix[r].v[var], numeric[r],
                      kNumericJacobianRelTol * std::max(1.0, std::abs(numeric[r])))
              << Name(k) << ": pixel " << r << " wrt variable " << var << " at "
              << point.transpose();
        }
      }
    }
  }
}

// ---- Round trips ----

// How far out the round trips go: 1 deg inside the edge; unified with xi <= 1 and radtan (its
// sphere image grows without bound) to 135 deg: at xi = 0.9, 138.5 deg (m = 4.4) its radtan's
// fixed point stops contracting, and UnprojectToRay refuses from there on.
double Reach(const CameraIntrinsics& k) {
  const double inside = EdgeAngle(k) - 1 * kDeg;
  const bool unbounded_radtan = k.family == LensFamily::kUnified && k.xi <= 1 && k.k1 != 0;
  return unbounded_radtan ? std::min(inside, 135 * kDeg) : inside;
}

// UnprojectToRay(Project(P)) = P / |P| on a grid of angles out to Reach().
// Mutations caught: Mei's lift with f + xi for f - xi; the eucm lift without beta in mz; the
// double sphere's root with -sqrt; the ray left unnormalised.
TEST(UnprojectToRay, InvertsProjectOutToTheEdge) {
  for (const CameraIntrinsics& k : AllLenses()) {
    const double limit = Reach(k);
    double max_err = 0;
    for (int i = 0; i <= 40; ++i) {
      const double theta = limit * i / 40;
      for (double azimuth = 0.05; azimuth < 2 * M_PI; azimuth += 0.4) {
        const Eigen::Vector3d ray = Ray(theta, azimuth);
        Eigen::Vector2d pixel;
        Eigen::Vector3d back;
        ASSERT_TRUE(ProjectPoint(k, 3.0 * ray, &pixel)) << Name(k) << " theta " << theta;
        ASSERT_TRUE(UnprojectToRay(k, pixel, &back)) << Name(k) << " theta " << theta;
        max_err = std::max(max_err, (back - ray).norm());
      }
    }
    EXPECT_LT(max_err, kRayRoundTripTol) << Name(k);
    Measured("ray round trip " + Name(k) + " to deg " + std::to_string(limit / kDeg), max_err);
    EXPECT_GT(limit, 95 * kDeg) << Name(k) << " sees less than 190 deg";
  }
}

// The smallest normalised image radius (A^-1 pixel) of the rays at angle theta.
double InnerImageRadius(const CameraIntrinsics& k, double theta) {
  double radius = 1e300;
  for (double azimuth = 0; azimuth < 2 * M_PI; azimuth += 0.01) {
    Eigen::Vector2d pixel;
    if (!ProjectPoint(k, Ray(theta, azimuth), &pixel)) return 0;
    radius = std::min(radius, (k.Matrix().inverse() * pixel.homogeneous()).hnormalized().norm());
  }
  return radius;
}

// Project(UnprojectToRay(pixel)) = pixel on a raster over a 1280 x 960 image: every pixel that
// unprojects projects back, and none is refused inside the image of the rays at Reach().
// Mutations caught: the ray left unnormalised; unified's lift with sqrt(|s|) in place of refusing
// s < 0 (past xi = 1.6's rim).
TEST(UnprojectToRay, ProjectInvertsItOnAnImageRaster) {
  for (const CameraIntrinsics& k : AllLenses()) {
    const double edge = EdgeAngle(k);
    const double inner = InnerImageRadius(k, Reach(k));
    double max_err = 0;
    int lifted = 0;
    for (double u = 1; u < 1280; u += 16) {
      for (double v = 1; v < 960; v += 12) {
        const Eigen::Vector2d pixel(u, v);
        Eigen::Vector3d ray;
        if (!UnprojectToRay(k, pixel, &ray)) {
          const double radius = (k.Matrix().inverse() * pixel.homogeneous()).hnormalized().norm();
          EXPECT_GT(radius, inner) << Name(k) << ": refused " << pixel.transpose();
          continue;
        }
        ++lifted;
        EXPECT_NEAR(ray.norm(), 1.0, 1e-15);
        EXPECT_LT(std::acos(ray.z()), edge + 1e-9) << Name(k);
        Eigen::Vector2d back;
        ASSERT_TRUE(ProjectPoint(k, 5.0 * ray, &back)) << Name(k) << " " << pixel.transpose();
        max_err = std::max(max_err, (back - pixel).norm());
      }
    }
    EXPECT_LT(max_err, kPixelRoundTripTolPx) << Name(k);
    EXPECT_GT(lifted, 1000) << Name(k);
    Measured("pixel round trip " + Name(k) + " max px", max_err);
  }
}

// UndistortNormalized and UnprojectPixel serve the omnidirectional families in front (Z > 0) and
// refuse the rays behind. Mutation caught: Mei's lift with f + xi.
TEST(UnprojectPixel, OmnidirectionalFamiliesInFrontOnly) {
  for (const CameraIntrinsics& k : AllLenses()) {
    Eigen::Vector2d pixel, normalized;
    const Eigen::Vector3d front(0.4, -0.3, 1.0), behind = 2.0 * Ray(95 * kDeg, 0.3);
    ASSERT_TRUE(ProjectPoint(k, front, &pixel));
    ASSERT_TRUE(UnprojectPixel(k, pixel, &normalized)) << Name(k);
    EXPECT_LT((normalized - front.hnormalized()).norm(), 1e-10) << Name(k);
    ASSERT_TRUE(ProjectPoint(k, behind, &pixel)) << Name(k);
    EXPECT_FALSE(UnprojectPixel(k, pixel, &normalized)) << Name(k);
  }
}

// ---- The valid region's edge ----

// Project accepts the ray 1e-6 rad inside the edge the angle form locates and refuses it 1e-6 rad
// outside, at several azimuths; beyond it the image would fold over (or the denominator flip).
// Mutations caught: basalt's double-sphere w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1) in place of
// the exact one (edges at 140.9 and 149.5 deg for 142.5 and 158.4; 164.8 for 140.3 with xi = 1.3,
// past the rim); unified's w = xi for xi > 1; eucm's w without the alpha > 1/2 branch; beta
// dropped from eucm's d.
TEST(OmnidirectionalCameras, ProjectStopsAtTheEdgeOfTheValidRegion) {
  for (const CameraIntrinsics& k : AllLenses()) {
    const double edge = EdgeAngle(k);
    for (double azimuth : {0.0, 1.1, 2.9, 4.4}) {
      Eigen::Vector2d pixel(-7, -7);
      EXPECT_TRUE(ProjectPoint(k, 2.0 * Ray(edge - kEdgeStepRad, azimuth), &pixel)) << Name(k);
      pixel = Eigen::Vector2d(-7, -7);
      EXPECT_FALSE(ProjectPoint(k, 2.0 * Ray(edge + kEdgeStepRad, azimuth), &pixel)) << Name(k);
      EXPECT_EQ(pixel, Eigen::Vector2d(-7, -7));  // Untouched.
    }
    Eigen::Vector2d pixel;
    EXPECT_FALSE(ProjectPoint(k, Eigen::Vector3d::Zero(), &pixel)) << Name(k);
    EXPECT_FALSE(ProjectPoint(k, Eigen::Vector3d(0, 0, -1), &pixel)) << Name(k);
    Measured("edge " + Name(k) + " deg", edge / kDeg);
  }
}

// The pixels whose lift is bounded (eucm and double sphere with alpha > 1/2: r2 < 1/(beta (2 alpha
// - 1)); unified with xi > 1: the sphere's rim 1/(xi^2 - 1) before radtan; the double sphere with
// xi > 1: the line from the second centre tangent to the first sphere): 1e-7 relative inside the
// radius unprojects to a ray at the projection's edge; every radius from 1e-7 outside to 4 times
// out is refused (the double sphere with xi = 1.3 meets its sphere again behind the second centre
// for r in (2.9, 3.16): refused too).
// Mutations caught: the eucm limit without beta (1/(2 alpha - 1)); the double sphere's f > 0
// test dropped; unified's lift with sqrt(|s|) in place of refusing s < 0.
TEST(UnprojectToRay, StopsAtTheEdgeOfTheImage) {
  struct Case {
    CameraIntrinsics k;
    double radius;  // Of the image point (before radtan for unified) at the edge.
  };
  std::vector<Case> cases;
  for (const CameraIntrinsics& k : EucmLenses()) {
    if (k.alpha > 0.5) cases.push_back({k, 1 / std::sqrt(k.beta * (2 * k.alpha - 1))});
  }
  cases.push_back({UnifiedLenses()[0], 1 / std::sqrt(1.6 * 1.6 - 1)});
  cases.push_back({DoubleSphere(0.25, 0.6), 1 / std::sqrt(2 * 0.6 - 1)});
  cases.push_back({DoubleSphere(1.3, 0.55), DoubleSphereRadial(1.3, 0.55, std::acos(-1 / 1.3)).m});
  std::vector<double> outside = {1 + 1e-7};
  for (int i = 1; i <= 300; ++i) outside.push_back(1 + 0.01 * i);
  for (const Case& c : cases) {
    const double edge = EdgeAngle(c.k);
    for (double azimuth : {0.3, 2.0, 3.7, 5.5}) {
      auto pixel_at = [&](double scale) {
        const double x = c.radius * scale * std::cos(azimuth);
        const double y = c.radius * scale * std::sin(azimuth);
        double xd = x, yd = y;
        if (c.k.family == LensFamily::kUnified) {
          ApplyRadTan(c.k.k1, c.k.k2, c.k.p1, c.k.p2, 0.0, x, y, &xd, &yd);
        }
        return Eigen::Vector2d((c.k.Matrix() * Eigen::Vector3d(xd, yd, 1)).head<2>());
      };
      Eigen::Vector3d ray;
      ASSERT_TRUE(UnprojectToRay(c.k, pixel_at(1 - 1e-7), &ray)) << Name(c.k) << " " << azimuth;
      EXPECT_NEAR(std::acos(ray.z()), edge, 2e-3) << Name(c.k);
      for (double scale : outside) {
        EXPECT_FALSE(UnprojectToRay(c.k, pixel_at(scale), &ray))
            << Name(c.k) << " azimuth " << azimuth << " radius x " << scale;
      }
    }
  }
}

// Without a pixel limit (alpha <= 1/2, xi <= 1) the farthest pixels lift to rays just inside the
// edge, which project. Mutations caught: Mei's lift with f + xi; eucm's mz without beta.
TEST(UnprojectToRay, FarPixelsApproachTheEdgeFromInside) {
  for (const CameraIntrinsics& k :
       {Eucm(0.35, 0.9), DoubleSphere(0.6, 0.4), Unified(0.6, 0, 0, 0, 0)}) {
    const double edge = EdgeAngle(k);
    const Eigen::Vector2d pixel = (k.Matrix() * Eigen::Vector3d(300.0, -400.0, 1.0)).head<2>();
    Eigen::Vector3d ray;
    ASSERT_TRUE(UnprojectToRay(k, pixel, &ray)) << Name(k);
    const double theta = std::acos(ray.z());
    EXPECT_LT(theta, edge) << Name(k);
    EXPECT_GT(theta, edge - 1 * kDeg) << Name(k);
    Eigen::Vector2d back;
    EXPECT_TRUE(ProjectPoint(k, ray, &back)) << Name(k);
  }
}

// DistortionIsMonotoneAt(r2) (the renderer's fold-over guard) for rays in front: true exactly
// where the image point (signed, along the x axis) moves out with r = tan(theta). Unified's radtan
// folds in front for a strong k1; the sphere steps of the three families do not.
// Mutation caught: unified's radtan slope taken at r2 instead of the sphere image's m^2.
TEST(CameraIntrinsics, DistortionIsMonotoneWhereTheImageRadiusGrows) {
  std::vector<CameraIntrinsics> lenses = AllLenses();
  lenses.push_back(Unified(0.5, -0.6, 0.0, 0.0, 0.0));  // Folds at r2 = 1.91 (54 deg).
  lenses.push_back(Unified(1.6, -1.2, 0.1, 0.0, 0.0));  // At r2 = 20.6 (78 deg).
  for (const CameraIntrinsics& k : lenses) {
    int folded = 0;
    for (double r = 0.05; r < 6; r += 0.05) {
      auto radius = [&](double x) {
        Eigen::Vector2d pixel;
        EXPECT_TRUE(ProjectPoint(k, Eigen::Vector3d(x, 0, 1), &pixel));
        return (k.Matrix().inverse() * pixel.homogeneous()).hnormalized().x();
      };
      const bool grows = radius(r + 1e-6) > radius(r - 1e-6);
      EXPECT_EQ(k.DistortionIsMonotoneAt(r * r), grows) << Name(k) << " r " << r;
      folded += !grows;
    }
    const bool plain = k.family != LensFamily::kUnified || k.k1 > -0.5;
    EXPECT_EQ(folded == 0, plain) << Name(k);
  }
}

// DistortionIsMonotoneAlong(point) (the renderer's guard for any direction): for rays in front it
// is DistortionIsMonotoneAt(tan^2 theta); over every direction, past 90 deg too, it is true exactly
// where the point projects and its image radius (signed, along the x axis) grows with the angle
// from the axis; radtan and equidistant refuse Z <= 0.
// Mutation caught: unified's slope taken at (X^2 + Y^2) / Z^2 instead of the sphere image's m^2.
TEST(CameraIntrinsics, DistortionIsMonotoneAlongEveryDirection) {
  std::vector<CameraIntrinsics> lenses = AllLenses();
  lenses.push_back(Unified(0.5, -0.6, 0.0, 0.0, 0.0));  // Folds at 54 deg.
  lenses.push_back(Unified(1.6, -1.2, 0.1, 0.0, 0.0));  // At 78 deg.
  for (const CameraIntrinsics& k : lenses) {
    for (double theta = 0.5 * kDeg; theta < M_PI; theta += 0.5 * kDeg) {
      const Eigen::Vector3d p = 2.5 * Ray(theta, 0);
      auto radius = [&](double t) {
        Eigen::Vector2d pixel;
        if (!ProjectPoint(k, Ray(t, 0), &pixel)) return std::nan("");
        return (k.Matrix().inverse() * pixel.homogeneous()).hnormalized().x();
      };
      const bool grows = radius(theta + 1e-6) > radius(theta - 1e-6);  // False where NaN.
      EXPECT_EQ(k.DistortionIsMonotoneAlong(p), grows) << Name(k) << " theta " << theta / kDeg;
      if (theta < 89 * kDeg) {
        const double t = std::tan(theta);
        EXPECT_EQ(k.DistortionIsMonotoneAlong(p), k.DistortionIsMonotoneAt(t * t)) << Name(k);
      }
    }
  }
  CameraIntrinsics radtan;
  CameraIntrinsics equidistant;
  equidistant.family = LensFamily::kEquidistant;
  for (const CameraIntrinsics& k : {radtan, equidistant}) {
    EXPECT_TRUE(k.DistortionIsMonotoneAlong(Ray(60 * kDeg, 1.0)));
    EXPECT_FALSE(k.DistortionIsMonotoneAlong(Eigen::Vector3d(0.6, 0.8, 0.0)));
    EXPECT_FALSE(k.DistortionIsMonotoneAlong(Ray(100 * kDeg, 1.0)));
  }
}

// ---- Check ----

// Mutation caught: Check() without the family test (xi on radtan accepted), alpha's range as
// (0, 1] (alpha = 0, the pinhole, refused); the double sphere's xi bound as >= 0 (xi = -0.99
// refused) or dropped (xi = -1 accepted).
TEST(CameraIntrinsics, CheckRefusesOmnidirectionalFieldsOutOfRangeOrOfAnotherFamily) {
  // The lenses tested, and the ranges' closed ends: alpha = 0 (the pinhole) and 1, xi = 0.
  std::vector<CameraIntrinsics> valid = AllLenses();
  for (const CameraIntrinsics& k :
       {Eucm(0.0, 1.0), Eucm(1.0, 2.0), DoubleSphere(0.0, 0.0), DoubleSphere(0.0, 1.0),
        DoubleSphere(-0.99, 0.5), Unified(0.0, 0, 0, 0, 0)}) {
    valid.push_back(k);
  }
  for (const CameraIntrinsics& k : valid) {
    std::string why;
    EXPECT_TRUE(k.Check(&why)) << Name(k) << ": " << why;
  }
  const struct {
    CameraIntrinsics k;
    std::vector<std::string> words;  // The message must name the field and the family.
  } cases[] = {
      {Unified(-0.1, 0, 0, 0, 0), {"xi", "unified"}},
      {DoubleSphere(-1.0, 0.5), {"xi", "double-sphere", "> -1"}},
      {DoubleSphere(-1.5, 0.5), {"xi", "double-sphere"}},
      {Eucm(-0.01, 1.0), {"alpha", "eucm", "[0, 1]"}},
      {Eucm(1.01, 1.0), {"alpha", "eucm"}},
      {DoubleSphere(0.3, 1.2), {"alpha", "double-sphere"}},
      {DoubleSphere(0.3, -0.5), {"alpha", "double-sphere"}},
      {Eucm(0.5, 0.0), {"beta", "eucm", "> 0"}},
      {Eucm(0.5, -1.0), {"beta", "eucm"}},
      {Eucm(0.5, NAN), {"beta", "finite"}},
  };
  for (const auto& c : cases) {
    std::string why;
    EXPECT_FALSE(c.k.Check(&why)) << Name(c.k);
    for (const std::string& w : c.words) EXPECT_NE(why.find(w), std::string::npos) << why;
  }
  // Coefficients of another family, away from their neutral value.
  auto with = [](CameraIntrinsics k, double CameraIntrinsics::*field, double value) {
    k.*field = value;
    return k;
  };
  CameraIntrinsics radtan = Camera(LensFamily::kRadTan), equi = Camera(LensFamily::kEquidistant);
  const struct {
    CameraIntrinsics k;
    const char* field;
  } foreign[] = {
      {with(UnifiedLenses()[0], &CameraIntrinsics::k3, 0.01), "k3"},
      {with(UnifiedLenses()[0], &CameraIntrinsics::k4, 0.01), "k4"},
      {with(UnifiedLenses()[0], &CameraIntrinsics::alpha, 0.5), "alpha"},
      {with(EucmLenses()[0], &CameraIntrinsics::p1, 1e-3), "p1"},
      {with(EucmLenses()[0], &CameraIntrinsics::k1, 0.1), "k1"},
      {with(EucmLenses()[0], &CameraIntrinsics::xi, 0.5), "xi"},
      {with(DoubleSphereLenses()[0], &CameraIntrinsics::beta, 1.2), "beta"},
      {with(DoubleSphereLenses()[0], &CameraIntrinsics::k2, 0.1), "k2"},
      {with(radtan, &CameraIntrinsics::xi, 0.5), "xi"},
      {with(radtan, &CameraIntrinsics::beta, 0.9), "beta"},
      {with(equi, &CameraIntrinsics::alpha, 0.4), "alpha"},
  };
  for (const auto& c : foreign) {
    std::string why;
    EXPECT_FALSE(c.k.Check(&why)) << Name(c.k) << " with " << c.field;
    EXPECT_EQ(why.find(c.field), 0u) << why;  // Named first...
    EXPECT_NE(why.find(std::string("the ") + ToString(c.k.family) + " model"), std::string::npos)
        << why;  // ...with the family.
  }
}

}  // namespace
}  // namespace calibench
