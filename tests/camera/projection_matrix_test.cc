// theta <-> M and the recovery of a camera from theta (camera/projection_matrix.h).
#include "camera/projection_matrix.h"

#include <gtest/gtest.h>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

// Recovery is a handful of square roots and a 3x3 inverse on entries up to ~1e4: relative
// rounding stays near 1e-12; the bound is 1e-9.
constexpr double kRecoveryRelTol = 1e-9;

std::vector<Eigen::Vector3d> PointsInFront(const Rigid3& cam_from_parent, Rng* rng) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 6; ++i) {
    const double z = rng->Uniform(2, 6), y = rng->Uniform(-1, 1);  // Last first: util/random.h.
    const Eigen::Vector3d in_cam(rng->Uniform(-1, 1), y, z);
    points.push_back(cam_from_parent.Inverse() * in_cam);
  }
  return points;
}

TEST(Theta, RowsOfMAndRegressorIdentity) {
  Matrix34d m;
  m << 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12;
  const Vector16d theta = ThetaFromM(m);
  EXPECT_EQ(theta.segment<4>(4), Eigen::Vector4d(5, 6, 7, 8));
  EXPECT_EQ(theta.segment<4>(12), Eigen::Vector4d(9, 10, 11, 12));
  EXPECT_EQ(MFromTheta(theta), m);
}

TEST(Theta, RecoveryIsExactOnRandomValidCameras) {
  Rng rng(2024);
  for (int trial = 0; trial < 1000; ++trial) {
    const CameraIntrinsics k = RandomIntrinsics({}, &rng);
    const Rigid3 cam_from_parent = RandomPose(10, &rng);
    const auto points = PointsInFront(cam_from_parent, &rng);
    // Any nonzero scale, either sign: M is known only up to scale.
    const double scale = (rng.Uniform() < 0.5 ? -1 : 1) * std::exp(rng.Uniform(-5, 5));
    DecomposedCamera cam;
    std::string why;
    ASSERT_TRUE(RecoverCamera(scale * ThetaFromCamera(k, cam_from_parent), points, &cam, &why))
        << why;
    auto rel = [](double a, double b) { return std::abs(a - b) / std::max(1.0, std::abs(b)); };
    EXPECT_LT(rel(cam.intrinsics.fku_px, k.fku_px), kRecoveryRelTol);
    EXPECT_LT(rel(cam.intrinsics.fkv_px, k.fkv_px), kRecoveryRelTol);
    EXPECT_LT(rel(cam.intrinsics.phi_deg, k.phi_deg), kRecoveryRelTol);
    EXPECT_LT(rel(cam.intrinsics.u0_px, k.u0_px), kRecoveryRelTol);
    EXPECT_LT(rel(cam.intrinsics.v0_px, k.v0_px), kRecoveryRelTol);
    const Rigid3 parent_from_cam = cam_from_parent.Inverse();
    EXPECT_LT((cam.parent_from_cam.rotation - parent_from_cam.rotation).norm(), kRecoveryRelTol);
    EXPECT_LT((cam.parent_from_cam.translation - parent_from_cam.translation).norm(),
              kRecoveryRelTol * std::max(1.0, parent_from_cam.translation.norm()));
    EXPECT_LT(cam.orthogonality_defect, 1e-9);
    EXPECT_FALSE(cam.improper);
    EXPECT_NEAR(cam.lambda, scale, 1e-9 * std::abs(scale));  // Cheirality picked the sign.
  }
}

TEST(Theta, ImproperRotationIsRecoveredAndFlagged) {
  CameraIntrinsics k{810, 820, 86, 320, 240};
  Rigid3 parent_from_cam;
  parent_from_cam.rotation << 0, 1, 0, 0, 0, 1, -1, 0, 0;  // Thesis camera 3 as printed.
  parent_from_cam.translation = {1, -4, -2};
  const Rigid3 cam_from_parent = parent_from_cam.Inverse();
  Rng rng(1);
  DecomposedCamera cam;
  ASSERT_TRUE(RecoverCamera(ThetaFromCamera(k, cam_from_parent),
                            PointsInFront(cam_from_parent, &rng), &cam, nullptr));
  EXPECT_TRUE(cam.improper);
  EXPECT_LT((cam.parent_from_cam.rotation - parent_from_cam.rotation).norm(), 1e-12);
  EXPECT_NEAR(cam.intrinsics.fku_px, 810, 1e-9);
}

TEST(Theta, DegenerateMatricesFailWithAReason) {
  std::string why;
  DecomposedCamera cam;
  EXPECT_FALSE(RecoverCamera(Vector16d::Zero(), {}, &cam, &why));
  EXPECT_NE(why.find("third row"), std::string::npos);
  Vector16d rank_deficient = Vector16d::Zero();
  rank_deficient.segment<4>(0) << 1, 0, 0, 0;
  rank_deficient.segment<4>(4) << 1, 0, 0, 0;  // Rows 1 and 2 parallel.
  rank_deficient.segment<4>(8) << 0, 0, 1, 1;
  EXPECT_FALSE(RecoverCamera(rank_deficient, {}, &cam, &why));
  EXPECT_NE(why.find("degenerate"), std::string::npos);
  Vector16d nan_theta = Vector16d::Ones();
  nan_theta[3] = std::nan("");
  EXPECT_FALSE(RecoverCamera(nan_theta, {}, &cam, &why));
}

}  // namespace
}  // namespace calibench
