// The omnidirectional lens families of camera/camera.h (unified, eucm, double-sphere): projection
// against OpenCV's cv::omnidir and against the papers' models written with angles, Jet
// derivatives, and round trips through UnprojectToRay out to each model's edge (the edge itself
// and Check()'s refusals: lens_families_edge_test.cc).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <opencv2/ccalib/omnidir.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "tests/camera/omnidirectional_lenses.h"

namespace calibench {
namespace lens_test {
namespace {

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

// How far out the round trips go: 1 deg inside the edge (unified with xi <= 1 and radtan too,
// whose sphere image grows without bound: at xi = 0.9 the radtan's fixed point stops contracting
// at 138.5 deg, m = 4.4, and Newton takes over out to the sphere's edge at 154.2 deg).
double Reach(const CameraIntrinsics& k) { return EdgeAngle(k) - 1 * kDeg; }

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

}  // namespace
}  // namespace lens_test
}  // namespace calibench
