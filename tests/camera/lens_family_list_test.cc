// Every family of the list (camera/lens_families.h), by looping over LensFamilies(): a family
// added to the list is tested here without a line of this file changing. Each family's example
// lens (LensFamilyInfo::example_lens) must round-trip project/unproject over a grid of rays across
// its valid field, its analytic Jacobian (batch/projection_jacobian.h) must equal ceres::Jet's
// derivatives of Project<T>, and its declaration must agree with the functions that read it.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "batch/projection_jacobian.h"
#include "camera/camera.h"

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;
// Distance between a unit ray and its round trip (~ the angle): the inverses iterate to 1e-12 in
// the image plane (camera.cc), which near a wide lens's edge is ~1e-10 rad; 1e-8 leaves two decades
// of margin.
constexpr double kRoundTripRad = 1e-8;
// Analytic against Jet derivatives: the same expressions reordered, so agreement to ~1e-13 of the
// largest entry; 1e-9 relative catches any wrong term (a wrong term is off by O(1)).
constexpr double kJacobianRelative = 1e-9;

// The family's example camera: 960 x 600, about 330 px focal length on the axis, slight skew so
// that every pinhole derivative is exercised.
CameraIntrinsics Example(const LensFamilyInfo& info) {
  CameraIntrinsics k;
  k.family = info.family;
  k.fku_px = 330 * info.example_focal_scale;
  k.fkv_px = 331 * info.example_focal_scale;
  k.phi_deg = 89.9;
  k.u0_px = 482;
  k.v0_px = 297;
  for (int i = 0; i < 5; ++i) {
    if (double* field = LensField(&k, info.lens_params[i])) *field = info.example_lens[i];
  }
  return k;
}

// Unit rays at angle theta from the axis, azimuth phi.
Eigen::Vector3d Ray(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// The grid: every 5 deg from the axis out to 175 deg, 8 azimuths; along each azimuth the rays up
// to the first one outside the family's valid, monotone field (DistortionIsMonotoneAlong) or
// imaged more than an image size off the 960 x 600 image (radtan and equidistant reach 90 deg
// only at infinity).
std::vector<Eigen::Vector3d> ValidGrid(const CameraIntrinsics& k) {
  std::vector<Eigen::Vector3d> rays;
  for (int a = 0; a < 8; ++a) {
    for (double theta_deg = 0; theta_deg <= 175; theta_deg += 5) {
      if (!InfoOf(k.family).sees_past_90 && theta_deg >= 90) break;  // Its edge: Z > 0.
      const Eigen::Vector3d ray = Ray(theta_deg * kDeg, a * M_PI / 4 + 0.1);
      Eigen::Vector2d pixel;
      if (!k.DistortionIsMonotoneAlong(ray) || !ProjectPoint(k, ray, &pixel) ||
          pixel.cwiseAbs().maxCoeff() > 2 * 960) {
        break;
      }
      rays.push_back(ray);
    }
  }
  return rays;
}

TEST(LensFamilyList, DeclarationsAgreeWithTheirReaders) {
  ASSERT_GE(LensFamilies().size(), 5u);
  for (const LensFamilyInfo& info : LensFamilies()) {
    SCOPED_TRACE(info.name);
    EXPECT_EQ(&InfoOf(info.family), &info);
    EXPECT_STREQ(ToString(info.family), info.name);
    for (int i = 0; i < 5; ++i) {
      EXPECT_STREQ(ParamNames(info.family)[5 + i], info.lens_params[i]);
      const std::string name = info.lens_params[i];
      CameraIntrinsics k;
      EXPECT_EQ(LensField(k, name) != nullptr, name != "-") << name;
    }
    // The family's full model frees every slot it names.
    const LensModel full = FullModelOf(info.family);
    EXPECT_EQ(FamilyOf(full), info.family);
    // The example lens is valid and survives Params/FromParams exactly.
    const CameraIntrinsics k = Example(info);
    std::string why;
    EXPECT_TRUE(k.Check(&why)) << why;
    const std::array<double, 10> params = k.Params();
    EXPECT_EQ(CameraIntrinsics::FromParams(params.data(), info.family).Params(), params);
    // Each range refuses a value just outside it, as CameraIntrinsics::Check says.
    for (const LensParamRange& range : info.ranges) {
      if (range.name == nullptr) continue;
      CameraIntrinsics bad = k;
      *LensField(&bad, range.name) = range.lower_open ? range.lower : range.lower - 1e-6;
      EXPECT_FALSE(bad.Check(&why)) << range.name;
      EXPECT_NE(why.find(std::string(range.name) + " must " +
                         (range.upper != kNoUpperBound ? "lie in [" : "be >")),
                std::string::npos)
          << why;
      if (range.upper != kNoUpperBound) {
        *LensField(&bad, range.name) = range.upper + 1e-6;
        EXPECT_FALSE(bad.Check(&why)) << range.name;
      }
    }
  }
}

TEST(LensFamilyList, EveryFamilyRoundTripsOverItsField) {
  for (const LensFamilyInfo& info : LensFamilies()) {
    SCOPED_TRACE(info.name);
    const CameraIntrinsics k = Example(info);
    const std::vector<Eigen::Vector3d> rays = ValidGrid(k);
    // The example lenses see at least 60 deg from the axis all round (13 rings of 8), and the
    // families that see past 90 deg do so.
    EXPECT_GE(rays.size(), 13u * 8u);
    double widest = 0;
    for (const Eigen::Vector3d& ray : rays) {
      Eigen::Vector2d pixel;
      ASSERT_TRUE(ProjectPoint(k, 3.0 * ray, &pixel));
      Eigen::Vector3d back;
      ASSERT_TRUE(UnprojectToRay(k, pixel, &back)) << ray.transpose();
      EXPECT_LT((back - ray).norm(), kRoundTripRad) << ray.transpose();
      widest = std::max(widest, std::acos(ray.z()));
      if (ray.z() > 0.2) {  // The normalised inverse too, in front (below 78 deg).
        Eigen::Vector2d normalized;
        ASSERT_TRUE(UnprojectPixel(k, pixel, &normalized));
        EXPECT_LT((normalized - ray.hnormalized()).norm(), kRoundTripRad * (1 + ray.squaredNorm()));
      }
    }
    EXPECT_EQ(widest > 90 * kDeg, info.sees_past_90) << widest / kDeg;
    Eigen::Vector2d pixel;
    EXPECT_EQ(ProjectPoint(k, Ray(100 * kDeg, 0.3), &pixel), info.sees_past_90);
  }
}

TEST(LensFamilyList, AnalyticJacobianEqualsJet) {
  using Jet = ceres::Jet<double, 13>;  // 3 point coordinates, then the 10 intrinsics.
  for (const LensFamilyInfo& info : LensFamilies()) {
    SCOPED_TRACE(info.name);
    const CameraIntrinsics k = Example(info);
    const std::array<double, 10> params = k.Params();
    int checked = 0;
    for (const Eigen::Vector3d& ray : ValidGrid(k)) {
      const Eigen::Vector3d point = 2.5 * ray;
      ProjectionJacobian analytic;
      ASSERT_TRUE(ProjectWithJacobian(info.family, params.data(), point, true, &analytic));
      Jet point_jet[3], params_jet[10], pixel_jet[2];
      for (int i = 0; i < 3; ++i) point_jet[i] = Jet(point[i], i);
      for (int i = 0; i < 10; ++i) params_jet[i] = Jet(params[i], 3 + i);
      ASSERT_TRUE(ProjectLens(info.family, params_jet, point_jet, pixel_jet));
      for (int r = 0; r < 2; ++r) {
        EXPECT_NEAR(analytic.pixel[r], pixel_jet[r].a,
                    1e-9 * std::max(1.0, std::abs(pixel_jet[r].a)));
        const double scale = std::max(1.0, pixel_jet[r].v.cwiseAbs().maxCoeff());
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(analytic.d_point(r, c), pixel_jet[r].v[c], kJacobianRelative * scale);
        }
        for (int c = 0; c < 10; ++c) {
          // Slots the family leaves unused have no derivative (the analytic one is 0).
          const double jet =
              ParamNames(info.family)[c] == std::string("-") ? 0.0 : pixel_jet[r].v[3 + c];
          EXPECT_NEAR(analytic.d_intrinsics(r, c), jet, kJacobianRelative * scale) << c;
        }
      }
      ++checked;
    }
    EXPECT_GE(checked, 13 * 8);
  }
}

}  // namespace
}  // namespace calibench
