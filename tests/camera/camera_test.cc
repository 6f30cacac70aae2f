#include "camera/camera.h"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

// Round trips through A and A^-1 lose ~1e-16 relative per operation on values up to 2000 px.
constexpr double kRoundTripTolPx = 1e-9;
// Central differences with h = 1e-6 have truncation error O(h^2 * |f'''|) ~ 1e-9 relative here.
constexpr double kNumericJacobianRelTol = 1e-6;

TEST(CameraIntrinsics, MatrixMatchesThesisFormula) {
  CameraIntrinsics k{822, 813, 87, 321, 239};
  const Eigen::Matrix3d a = k.Matrix();
  const double phi = 87 * M_PI / 180;
  EXPECT_DOUBLE_EQ(a(0, 0), 822);
  EXPECT_NEAR(a(0, 1), -822 / std::tan(phi), 1e-12);
  EXPECT_NEAR(a(1, 1), 813 / std::sin(phi), 1e-12);
  EXPECT_EQ(a(1, 0), 0);
  EXPECT_EQ(a(2, 2), 1);
}

TEST(CameraIntrinsics, FromMatrixInvertsMatrixOnRandomCameras) {
  Rng rng(7);
  for (int i = 0; i < 1000; ++i) {
    const CameraIntrinsics k = RandomIntrinsics({}, &rng);
    const CameraIntrinsics back = CameraIntrinsics::FromMatrix(k.Matrix());
    EXPECT_NEAR(back.fku_px, k.fku_px, kRoundTripTolPx);
    EXPECT_NEAR(back.fkv_px, k.fkv_px, kRoundTripTolPx);
    EXPECT_NEAR(back.phi_deg, k.phi_deg, 1e-11);
    EXPECT_NEAR(back.u0_px, k.u0_px, kRoundTripTolPx);
    EXPECT_NEAR(back.v0_px, k.v0_px, kRoundTripTolPx);
  }
}

TEST(CameraIntrinsics, CheckRejectsInvalidValuesAndNamesThem) {
  std::string why;
  CameraIntrinsics k;
  EXPECT_TRUE(k.Check(&why));
  k.fku_px = -1;
  EXPECT_FALSE(k.Check(&why));
  EXPECT_NE(why.find("fku_px"), std::string::npos);
  k = CameraIntrinsics();
  k.phi_deg = 180;
  EXPECT_FALSE(k.Check(&why));
  EXPECT_NE(why.find("phi_deg"), std::string::npos);
  k.phi_deg = 0;
  EXPECT_FALSE(k.Check(&why));
  k = CameraIntrinsics();
  k.fkv_px = std::nan("");
  EXPECT_FALSE(k.Check(&why));
}

// Without distortion, Project(p) == hnormalized(A p): an independent computation.
TEST(PinholeSkewCamera, ProjectionEqualsMatrixProductOnAGrid) {
  Rng rng(11);
  for (int c = 0; c < 50; ++c) {
    const CameraIntrinsics k = RandomIntrinsics({}, &rng);
    const auto params = k.Params();
    for (double x = -2; x <= 2; x += 0.5) {
      for (double y = -2; y <= 2; y += 0.5) {
        const Eigen::Vector3d p(x, y, 3.0);
        Eigen::Vector2d pixel;
        ASSERT_TRUE(PinholeSkewCamera::Project(params.data(), p.data(), pixel.data()));
        const Eigen::Vector2d expected = (k.Matrix() * p).hnormalized();
        EXPECT_NEAR((pixel - expected).norm(), 0.0, kRoundTripTolPx);
        // And back: A^-1 [u v 1] is the normalised ray.
        const Eigen::Vector3d ray = k.Matrix().inverse() * pixel.homogeneous();
        EXPECT_NEAR((ray - p / p.z()).norm(), 0.0, 1e-12);
      }
    }
  }
}

TEST(PinholeSkewCamera, RadialDistortionScalesNormalisedCoordinates) {
  CameraIntrinsics k{800, 790, 90, 320, 240, -0.2, 0.05};
  const Eigen::Vector3d p(0.4, -0.3, 1.0);
  Eigen::Vector2d pixel;
  ASSERT_TRUE(ProjectPoint(k, p, &pixel));
  const double r2 = 0.25;
  const double d = 1 - 0.2 * r2 + 0.05 * r2 * r2;
  EXPECT_NEAR(pixel.x(), 800 * 0.4 * d + 320, 1e-12);
  EXPECT_NEAR(pixel.y(), 790 * -0.3 * d + 240, 1e-12);
}

// OpenCV's tangential and k3 terms, written out by hand.
TEST(PinholeSkewCamera, TangentialDistortionFollowsOpenCv) {
  CameraIntrinsics k{800, 790, 90, 320, 240, -0.2, 0.05, 1e-3, -2e-3, 0.02};
  const double x = 0.4, y = -0.3, r2 = x * x + y * y;
  const double d = 1 - 0.2 * r2 + 0.05 * r2 * r2 + 0.02 * r2 * r2 * r2;
  const double xd = x * d + 2 * 1e-3 * x * y + -2e-3 * (r2 + 2 * x * x);
  const double yd = y * d + 1e-3 * (r2 + 2 * y * y) + 2 * -2e-3 * x * y;
  Eigen::Vector2d pixel;
  ASSERT_TRUE(ProjectPoint(k, Eigen::Vector3d(x, y, 1), &pixel));
  EXPECT_NEAR(pixel.x(), 800 * xd + 320, 1e-12);
  EXPECT_NEAR(pixel.y(), 790 * yd + 240, 1e-12);
}

TEST(PinholeSkewCamera, ReturnsFalseBehindTheCamera) {
  const auto params = CameraIntrinsics().Params();
  Eigen::Vector2d pixel(-7, -7);
  const Eigen::Vector3d behind(0.1, 0.2, -1.0), on_plane(0.1, 0.2, 0.0);
  EXPECT_FALSE(PinholeSkewCamera::Project(params.data(), behind.data(), pixel.data()));
  EXPECT_FALSE(PinholeSkewCamera::Project(params.data(), on_plane.data(), pixel.data()));
  EXPECT_EQ(pixel, Eigen::Vector2d(-7, -7));  // Untouched.
}

// Project() instantiated with ceres::Jet: its derivatives equal central differences.
TEST(PinholeSkewCamera, JetDerivativesMatchNumericDifferentiation) {
  using Jet = ceres::Jet<double, 13>;  // 10 parameters + 3 point coordinates.
  CameraIntrinsics k{812, 805, 84, 318, 236, -0.15, 0.03, 1e-3, -2e-3, 0.01};
  const auto params = k.Params();
  const std::array<double, 3> point = {0.35, -0.2, 2.5};
  Jet jp[10], jx[3], jpix[2];
  for (int i = 0; i < 10; ++i) jp[i] = Jet(params[i], i);
  for (int i = 0; i < 3; ++i) jx[i] = Jet(point[i], 10 + i);
  ASSERT_TRUE(PinholeSkewCamera::Project(jp, jx, jpix));

  auto eval = [&](int var, double delta) {
    std::array<double, 10> p = params;
    std::array<double, 3> x = point;
    if (var < 10)
      p[var] += delta;
    else
      x[var - 10] += delta;
    Eigen::Vector2d out;
    PinholeSkewCamera::Project(p.data(), x.data(), out.data());
    return out;
  };
  for (int var = 0; var < 13; ++var) {
    const double h =
        1e-6 * std::max(1.0, var < 10 ? std::abs(params[var]) : std::abs(point[var - 10]));
    const Eigen::Vector2d numeric = (eval(var, h) - eval(var, -h)) / (2 * h);
    for (int r = 0; r < 2; ++r) {
      EXPECT_NEAR(jpix[r].v[var], numeric[r],
                  kNumericJacobianRelTol * std::max(1.0, std::abs(numeric[r])))
          << "pixel " << r << " wrt variable " << var;
    }
  }
}

// A fisheye as TUM-VI's cameras (Kannala-Brandt coefficients of that size), with some skew.
CameraIntrinsics EquidistantCamera() {
  CameraIntrinsics k;
  k.family = LensFamily::kEquidistant;
  k.fku_px = 290.0, k.fkv_px = 291.5, k.phi_deg = 89.5, k.u0_px = 322.0, k.v0_px = 238.0;
  k.k1 = 0.0034, k.k2 = 0.0007, k.k3 = -0.0020, k.k4 = 0.0002;
  return k;
}

// An independent form of the equidistant model: theta is the angle between the ray and the
// optical axis (acos, not atan of the normalised radius), the image point lies theta_d along the
// ray's azimuth, then A.
TEST(PinholeEquiCamera, ProjectionEqualsTheAngleFormOfTheModel) {
  const CameraIntrinsics k = EquidistantCamera();
  for (double azimuth = 0.0; azimuth < 2 * M_PI; azimuth += 0.7) {
    for (double theta = 0.0; theta < 1.5; theta += 0.13) {
      const Eigen::Vector3d ray(std::sin(theta) * std::cos(azimuth),
                                std::sin(theta) * std::sin(azimuth), std::cos(theta));
      const double t2 = theta * theta;
      const double theta_d = theta * (1 + t2 * (k.k1 + t2 * (k.k2 + t2 * (k.k3 + t2 * k.k4))));
      const Eigen::Vector3d image_point(theta_d * std::cos(azimuth), theta_d * std::sin(azimuth),
                                        1);
      const Eigen::Vector2d expected = (k.Matrix() * image_point).head<2>();
      Eigen::Vector2d pixel;
      ASSERT_TRUE(ProjectPoint(k, 2.5 * ray, &pixel));
      EXPECT_LT((pixel - expected).norm(), kRoundTripTolPx) << "theta " << theta;
    }
  }
  Eigen::Vector2d pixel;
  EXPECT_FALSE(ProjectPoint(k, Eigen::Vector3d(1, 0, 0), &pixel));  // theta = 90 deg.
  EXPECT_FALSE(ProjectPoint(k, Eigen::Vector3d(0, 0, -1), &pixel));
}

// Jet derivatives of both families against central differences, including the equidistant
// model's r -> 0 branch (a point on the optical axis).
TEST(ProjectLens, JetDerivativesMatchNumericDifferentiationForEveryFamily) {
  using Jet = ceres::Jet<double, 13>;
  CameraIntrinsics radtan{812, 805, 84, 318, 236, -0.15, 0.03, 1e-3, -2e-3, 0.01};
  const struct {
    CameraIntrinsics k;
    std::array<double, 3> point;
  } cases[] = {{radtan, {0.35, -0.2, 2.5}},
               {EquidistantCamera(), {1.1, -0.7, 0.9}},
               {EquidistantCamera(), {0.0, 0.0, 1.0}}};
  for (const auto& c : cases) {
    const auto params = c.k.Params();
    Jet jp[10], jx[3], jpix[2];
    for (int i = 0; i < 10; ++i) jp[i] = Jet(params[i], i);
    for (int i = 0; i < 3; ++i) jx[i] = Jet(c.point[i], 10 + i);
    ASSERT_TRUE(ProjectLens(c.k.family, jp, jx, jpix));
    auto eval = [&](int var, double delta) {
      std::array<double, 10> p = params;
      std::array<double, 3> x = c.point;
      (var < 10 ? p[var] : x[var - 10]) += delta;
      Eigen::Vector2d out;
      ProjectLens(c.k.family, p.data(), x.data(), out.data());
      return out;
    };
    for (int var = 0; var < 13; ++var) {
      const double h =
          1e-6 * std::max(1.0, var < 10 ? std::abs(params[var]) : std::abs(c.point[var - 10]));
      const Eigen::Vector2d numeric = (eval(var, h) - eval(var, -h)) / (2 * h);
      for (int r = 0; r < 2; ++r) {
        EXPECT_NEAR(jpix[r].v[var], numeric[r],
                    kNumericJacobianRelTol * std::max(1.0, std::abs(numeric[r])))
            << ToString(c.k.family) << ": pixel " << r << " wrt variable " << var;
      }
    }
  }
}

// Undistort inverts the projection to 1e-10 (normalised) out to 80 degrees off axis.
TEST(UndistortNormalized, InvertsTheEquidistantLensToEightyDegrees) {
  const CameraIntrinsics k = EquidistantCamera();
  for (double x = -5.0; x <= 5.0; x += 0.5) {
    for (double y = -4.0; y <= 4.0; y += 0.5) {
      if (std::atan(std::hypot(x, y)) > 80 * M_PI / 180) continue;
      Eigen::Vector2d pixel;
      ASSERT_TRUE(ProjectPoint(k, Eigen::Vector3d(x, y, 1.0), &pixel));
      const Eigen::Vector2d distorted = (k.Matrix().inverse() * pixel.homogeneous()).head<2>();
      Eigen::Vector2d undistorted;
      ASSERT_TRUE(UndistortNormalized(k, distorted, &undistorted));
      EXPECT_LT((undistorted - Eigen::Vector2d(x, y)).norm(),
                1e-10 * std::max(1.0, std::hypot(x, y)));
    }
  }
}

// UnprojectPixel is ProjectPoint's inverse up to depth, for both families (radtan with skew and
// tangential terms, equidistant to 80 degrees): to 1e-9 in normalised coordinates.
TEST(UnprojectPixel, InvertsProjectPoint) {
  CameraIntrinsics radtan{800.0, 790.0, 89.0, 330.0, 235.0, -0.2, 0.05, 1e-3, -5e-4, 0.01};
  for (const CameraIntrinsics& k : {radtan, EquidistantCamera()}) {
    for (const Eigen::Vector3d& point :
         {Eigen::Vector3d(0.1, -0.2, 1.0), Eigen::Vector3d(-0.4, 0.3, 1.5),
          Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d(0.5, 0.35, 1.2)}) {
      Eigen::Vector2d pixel, normalized;
      ASSERT_TRUE(ProjectPoint(k, point, &pixel));
      ASSERT_TRUE(UnprojectPixel(k, pixel, &normalized)) << ToString(k.family);
      EXPECT_LT((normalized - point.hnormalized()).norm(), 1e-9) << ToString(k.family);
    }
  }
}

// FullModelOf: the model that frees every lens parameter of a family (what a camera file of that
// family is read as, and what a fit of a wide family estimates). Against the table above: a rule
// that took a family's first model would give pinhole for radtan and fail.
TEST(LensModels, FullModelOfFreesEveryParameterOfTheFamily) {
  const std::pair<LensFamily, const char*> expected[] = {
      {LensFamily::kRadTan, "pinhole-radtan5"},
      {LensFamily::kEquidistant, "pinhole-equi"},
      {LensFamily::kUnified, "unified"},
      {LensFamily::kEucm, "eucm"},
      {LensFamily::kDoubleSphere, "double-sphere"}};
  for (const auto& [family, name] : expected) {
    EXPECT_STREQ(ToString(FullModelOf(family)), name) << ToString(family);
  }
}

// Every lens model of the table: parses back from its name, its family's slot names cover its free
// parameters, Params() and FromParams() round-trip in its layout, and Check() refuses the
// coefficients the family lacks.
TEST(LensModels, TableRoundTripsAndFamiliesKeepTheirCoefficients) {
  const struct {
    const char* name;
    LensFamily family;
    std::vector<int> free;
    std::vector<const char*> slot_names;  // Of the free slots.
  } rows[] = {
      {"pinhole", LensFamily::kRadTan, {}, {}},
      {"pinhole-k2", LensFamily::kRadTan, {5, 6}, {"k1", "k2"}},
      {"pinhole-radtan4", LensFamily::kRadTan, {5, 6, 7, 8}, {"k1", "k2", "p1", "p2"}},
      {"pinhole-radtan5", LensFamily::kRadTan, {5, 6, 7, 8, 9}, {"k1", "k2", "p1", "p2", "k3"}},
      {"pinhole-equi", LensFamily::kEquidistant, {5, 6, 7, 8}, {"k1", "k2", "k3", "k4"}},
      {"unified", LensFamily::kUnified, {5, 6, 7, 8, 9}, {"xi", "k1", "k2", "p1", "p2"}},
      {"eucm", LensFamily::kEucm, {5, 6}, {"alpha", "beta"}},
      {"double-sphere", LensFamily::kDoubleSphere, {5, 6}, {"xi", "alpha"}},
  };
  ASSERT_EQ(LensModels().size(), std::size(rows));
  for (const auto& row : rows) {
    LensModel model;
    ASSERT_TRUE(ParseLensModel(row.name, &model)) << row.name;
    EXPECT_EQ(FamilyOf(model), row.family) << row.name;
    EXPECT_STREQ(ToString(FamilyOf(model)), ToString(row.family));
    const std::vector<int> fixed = FixedIntrinsics(model, true);
    for (size_t i = 0; i < row.free.size(); ++i) {
      EXPECT_STREQ(ParamNames(row.family)[row.free[i]], row.slot_names[i]) << row.name;
      EXPECT_EQ(std::count(fixed.begin(), fixed.end(), row.free[i]), 0) << row.name;
    }
    EXPECT_EQ(fixed.size(), 5 - row.free.size()) << row.name;  // The other lens slots.
  }
  for (const LensModelInfo& info : LensModels()) {
    LensModel parsed;
    ASSERT_TRUE(ParseLensModel(info.name, &parsed));
    EXPECT_EQ(parsed, info.model);
    EXPECT_EQ(FamilyOf(info.model), info.family);
    for (int i : info.free_distortion) {
      EXPECT_STRNE(ParamNames(info.family)[i], "-") << info.name << " frees slot " << i;
    }
  }
  const CameraIntrinsics equi = EquidistantCamera();
  const auto params = equi.Params();
  EXPECT_EQ(params[7], equi.k3);
  EXPECT_EQ(params[8], equi.k4);
  EXPECT_EQ(CameraIntrinsics::FromParams(params.data(), LensFamily::kEquidistant), equi);
  CameraIntrinsics bad = equi;
  bad.p1 = 1e-3;
  std::string why;
  EXPECT_FALSE(bad.Check(&why));
  EXPECT_NE(why.find("no tangential"), std::string::npos) << why;
  // An equidistant lens without k terms is still a fisheye (r = f theta): the renderer must cast
  // its rays through UndistortNormalized, not take the pinhole shortcut.
  CameraIntrinsics ideal_fisheye;
  ideal_fisheye.family = LensFamily::kEquidistant;
  EXPECT_TRUE(ideal_fisheye.IsDistorted());
  EXPECT_FALSE(CameraIntrinsics().IsDistorted());
  CameraIntrinsics radtan;
  radtan.k4 = 0.01;
  EXPECT_FALSE(radtan.Check(&why));
  EXPECT_NE(why.find("k4 belongs to the equidistant"), std::string::npos) << why;
  // The omnidirectional families' slots: [xi, k1, k2, p1, p2], [alpha, beta, 0, 0, 0], [xi,
  // alpha, 0, 0, 0]; FromParams() reads them back, and they are never a pinhole.
  CameraIntrinsics unified = EquidistantCamera(), eucm = unified, ds = unified;
  unified.family = LensFamily::kUnified, unified.k3 = unified.k4 = 0;
  unified.xi = 1.2, unified.k1 = -0.1, unified.k2 = 0.02, unified.p1 = 1e-3, unified.p2 = -1e-3;
  eucm.family = LensFamily::kEucm, eucm.k1 = eucm.k2 = eucm.k3 = eucm.k4 = 0;
  eucm.alpha = 0.6, eucm.beta = 1.1;
  ds.family = LensFamily::kDoubleSphere, ds.k1 = ds.k2 = ds.k3 = ds.k4 = 0;
  ds.xi = 0.3, ds.alpha = 0.55;
  const struct {
    CameraIntrinsics k;
    std::array<double, 5> slots;
  } layouts[] = {{unified, {1.2, -0.1, 0.02, 1e-3, -1e-3}},
                 {eucm, {0.6, 1.1, 0, 0, 0}},
                 {ds, {0.3, 0.55, 0, 0, 0}}};
  for (const auto& l : layouts) {
    ASSERT_TRUE(l.k.Check(&why)) << why;
    const auto p = l.k.Params();
    for (int i = 0; i < 5; ++i) EXPECT_EQ(p[5 + i], l.slots[i]) << ToString(l.k.family) << i;
    const CameraIntrinsics back = CameraIntrinsics::FromParams(p.data(), l.k.family);
    EXPECT_EQ(back, l.k) << ToString(l.k.family);
    EXPECT_EQ(back.xi, l.k.xi);
    EXPECT_EQ(back.alpha, l.k.alpha);
    EXPECT_EQ(back.beta, l.k.beta);
    EXPECT_TRUE(l.k.IsDistorted());
  }
}

}  // namespace
}  // namespace calibench
