// The omnidirectional lens families of camera/camera.h at the edge of their valid region:
// Project and UnprojectToRay stop there, the distortion stays monotone inside it; and Check()'s
// refusals of fields out of range or of another family.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "tests/camera/omnidirectional_lenses.h"

namespace calibench {
namespace lens_test {
namespace {

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
}  // namespace lens_test
}  // namespace calibench
