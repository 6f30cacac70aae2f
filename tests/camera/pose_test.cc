#include "camera/pose.h"

#include <gtest/gtest.h>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr double kSo3Tol = 1e-9;  // The tolerance every given rotation is checked to (scenario.cc).

TEST(Rotation, AcceptsProperRejectsImproperUnlessAllowed) {
  std::string why;
  Eigen::Matrix3d thesis_cam1;
  thesis_cam1 << -1, 0, 0, 0, 0, 1, 0, 1, 0;
  EXPECT_TRUE(CheckRotation(thesis_cam1, kSo3Tol, false, &why)) << why;
  Eigen::Matrix3d printed;  // Thesis cameras 2 and 3 as printed: det = -1.
  printed << 0, 1, 0, 0, 0, 1, -1, 0, 0;
  EXPECT_NEAR(printed.determinant(), -1.0, 1e-15);
  EXPECT_FALSE(CheckRotation(printed, kSo3Tol, false, &why));
  EXPECT_NE(why.find("improper"), std::string::npos);
  EXPECT_NE(why.find("allow_improper_rotation"), std::string::npos);
  EXPECT_TRUE(CheckRotation(printed, kSo3Tol, true, &why));
}

TEST(Rotation, OrthonormalityToleranceIsOneNanoUnit) {
  std::string why;
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r(0, 1) = 1e-11;  // defect ~1e-11: accepted.
  EXPECT_TRUE(CheckRotation(r, kSo3Tol, false, &why));
  r(0, 1) = 1e-8;  // defect ~1e-8: refused.
  EXPECT_FALSE(CheckRotation(r, kSo3Tol, false, &why));
  EXPECT_NE(why.find("orthonormal"), std::string::npos);
  r(0, 1) = std::nan("");
  EXPECT_FALSE(CheckRotation(r, kSo3Tol, false, &why));
}

TEST(Rotation, ExpMatchesAngleAxisAndAnglesRoundTrip) {
  Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    const double wz = rng.Normal(), wy = rng.Normal();  // Last first (util/random.h).
    const Eigen::Vector3d w(rng.Normal(), wy, wz);
    const Eigen::Matrix3d expected = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    EXPECT_LT((ExpSO3(w) - expected).norm(), 1e-14);
    // Geodesic angle between Exp(w) and I is |w| (wrapped to [0, pi]).
    const double angle = std::fmod(w.norm(), 2 * M_PI);
    const double wrapped = angle > M_PI ? 2 * M_PI - angle : angle;
    EXPECT_NEAR(RotationAngleDeg(ExpSO3(w), Eigen::Matrix3d::Identity()), wrapped * 180 / M_PI,
                1e-9);
    const Eigen::Matrix3d r = RandomRotation(&rng);
    EXPECT_LT((FromRollPitchYawDeg(RollPitchYawDeg(r)) - r).norm(), 1e-12);
  }
  EXPECT_LT((ExpSO3(Eigen::Vector3d(1e-10, 0, 0)) - Eigen::Matrix3d::Identity()).norm(), 2e-10);
}

TEST(Rotation, ProjectionToSo3RemovesNoise) {
  Rng rng(5);
  const Eigen::Matrix3d r = RandomRotation(&rng);
  Eigen::Matrix3d noisy = r;
  noisy(1, 2) += 1e-3;
  const Eigen::Matrix3d projected = ProjectToSO3(noisy);
  EXPECT_LT(OrthogonalityDefect(projected), 1e-14);
  EXPECT_NEAR(projected.determinant(), 1.0, 1e-14);
  EXPECT_LT(RotationAngleDeg(projected, r), 0.1);
  EXPECT_GT(OrthogonalityDefect(noisy), 1e-4);
}

// LogSO3 inverts ExpSO3 at the ends of its range, where the rotation vector is read off an
// almost-identity or an almost-half-turn matrix. The matrix entries carry ~1e-16 rounding, which
// the quaternion (Shepperd) and atan2 pass on unamplified: 1e-12 (relative near 0, where it is
// taken of max(angle, 1e-4) rad; absolute near pi) leaves room for rounding only.
constexpr double kLogRoundTrip = 1e-12;

TEST(Rotation, LogInvertsExpNearZero) {
  Rng rng(13);
  for (const double angle : {1e-2, 1e-5, 1e-8, 1e-11, 1e-14, 0.0}) {
    const double z = rng.Normal(), y = rng.Normal();  // Last first (util/random.h).
    const Eigen::Vector3d axis = Eigen::Vector3d(rng.Normal(), y, z).normalized();
    const Eigen::Vector3d w = angle * axis;
    EXPECT_LT((LogSO3(ExpSO3(w)) - w).norm(), kLogRoundTrip * std::max(angle, 1e-4))
        << "angle " << angle;
  }
}

TEST(Rotation, LogInvertsExpNearPi) {
  Rng rng(17);
  for (const double gap : {1e-2, 1e-5, 1e-8, 1e-11}) {
    const double z = rng.Normal(), y = rng.Normal();  // Last first (util/random.h).
    const Eigen::Vector3d axis = Eigen::Vector3d(rng.Normal(), y, z).normalized();
    const Eigen::Vector3d w = (M_PI - gap) * axis;
    EXPECT_LT((LogSO3(ExpSO3(w)) - w).norm(), kLogRoundTrip) << "pi - " << gap;
  }
  // At pi exactly, w and -w are one rotation: Log gives one of them, of length pi.
  const Eigen::Vector3d w = M_PI * Eigen::Vector3d(1, -2, 2).normalized();
  const Eigen::Vector3d log = LogSO3(ExpSO3(w));
  EXPECT_NEAR(log.norm(), M_PI, kLogRoundTrip);
  EXPECT_LT(std::min((log - w).norm(), (log + w).norm()), 1e-7);  // The axis: sqrt(eps) there.
  EXPECT_LT((ExpSO3(log) - ExpSO3(w)).norm(), kLogRoundTrip);
}

TEST(Rigid3, ComposeAndInverse) {
  Rng rng(9);
  const Rigid3 b_from_a = RandomPose(5, &rng), c_from_b = RandomPose(5, &rng);
  const Eigen::Vector3d point_in_a(0.3, -1.2, 2.0);
  const Rigid3 c_from_a = c_from_b * b_from_a;
  EXPECT_LT((c_from_a * point_in_a - c_from_b * (b_from_a * point_in_a)).norm(), 1e-12);
  EXPECT_LT((b_from_a.Inverse() * (b_from_a * point_in_a) - point_in_a).norm(), 1e-12);
}

}  // namespace
}  // namespace calibench
