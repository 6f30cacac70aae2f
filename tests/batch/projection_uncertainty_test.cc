// The projection uncertainty's algebra (batch/projection_uncertainty.h): the linear map from the
// poses' tangents against finite perturbations through Ceres' own quaternion manifold, and
// RefineCalibration's Cov(z) from the Schur complement against ceres::Covariance's dense inverse of
// the whole problem; the 11 x 11 covariance of an estimate (camera/estimate.h) mapped to Cov(z)
// against a shared-pose refinement's own. The Monte Carlo validation is
// tests/metrics/projection_uncertainty_study_test.
#include "batch/projection_uncertainty.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "batch/refine.h"
#include "batch/reprojection_error.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

const CameraIntrinsics kTruth{520.0, 515.0, 90.0, 322.0, 236.0, -0.21, 0.08};

// First order: the map's error on a perturbation of size h is O(h^2); with h = 1e-6 rad and
// 1e-6 m on poses ~0.5 m away, 1e-10 m of the point's ~1e-6 m motion is rounding and second order.
constexpr double kFirstOrderTolM = 1e-10;

TEST(ProjectionUncertainty, FrameShareIsTheFirstOrderMotionOfTheAveragedPoint) {
  Rng rng(7);
  std::vector<Rigid3> poses;
  poses.reserve(5);
  for (int v = 0; v < 5; ++v) poses.push_back(RandomPose(0.6, &rng));
  const int n = static_cast<int>(poses.size());
  const Eigen::Vector3d p(0.1, -0.2, 0.9);
  Eigen::Vector3d moved = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 1> frame_motion = Eigen::Matrix<double, 6, 1>::Zero();
  ceres::EigenQuaternionManifold manifold;
  for (const Rigid3& pose : poses) {
    Eigen::Matrix<double, 6, 1> tangent;
    for (int k = 0; k < 6; ++k) tangent[k] = 1e-6 * rng.Normal();
    const Eigen::Quaterniond q(pose.rotation);
    const double x[4] = {q.x(), q.y(), q.z(), q.w()};
    double x_plus[4];
    ASSERT_TRUE(manifold.Plus(x, tangent.data(), x_plus));
    const Eigen::Matrix3d rotation =
        Eigen::Quaterniond(x_plus[3], x_plus[0], x_plus[1], x_plus[2]).toRotationMatrix();
    const Eigen::Vector3d point_in_board = pose.rotation.transpose() * (p - pose.translation);
    moved += rotation * point_in_board + pose.translation + tangent.tail<3>();
    frame_motion += PoseTangentToFrameShare(pose, n) * tangent;
  }
  moved /= n;
  const Eigen::Vector3d predicted = p - Hat(p) * frame_motion.head<3>() + frame_motion.tail<3>();
  EXPECT_LT((moved - predicted).norm(), kFirstOrderTolM);
}

// Cov(z) from ceres::Covariance over every block (the whole inverse, no Schur complement).
ProjectionCovariance::Matrix DenseCovZ(const std::vector<View>& views, const RefineResult& fit,
                                       const RefineOptions& options) {
  ceres::Problem problem;
  std::array<double, 10> k = fit.intrinsics.Params();
  std::vector<std::array<double, 4>> q(views.size());
  std::vector<std::array<double, 3>> t(views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    const Eigen::Quaterniond r(fit.cam_from_object[v].rotation);
    q[v] = {r.x(), r.y(), r.z(), r.w()};
    t[v] = {fit.cam_from_object[v].translation.x(), fit.cam_from_object[v].translation.y(),
            fit.cam_from_object[v].translation.z()};
    for (size_t i = 0; i < views[v].points.size(); ++i) {
      problem.AddResidualBlock(
          ReprojectionError::Create(views[v].pixels[i], views[v].points[i], kTruth.family), nullptr,
          k.data(), q[v].data(), t[v].data());
    }
    problem.SetManifold(q[v].data(), new ceres::EigenQuaternionManifold);
  }
  const std::vector<int> fixed = FixedIntrinsics(options.model, options.estimate_skew);
  problem.SetManifold(k.data(), new ceres::SubsetManifold(10, fixed));
  std::vector<const double*> blocks = {k.data()};
  for (size_t v = 0; v < views.size(); ++v) {
    blocks.push_back(q[v].data());
    blocks.push_back(t[v].data());
  }
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(cov_options);
  EXPECT_TRUE(covariance.Compute(blocks, &problem));
  const int free = 10 - static_cast<int>(fixed.size());
  const int n = free + 6 * static_cast<int>(views.size());
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> sigma(n, n);
  EXPECT_TRUE(covariance.GetCovarianceMatrixInTangentSpace(blocks, sigma.data()));
  // L: tangent -> z.
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(16, n);
  int col = 0;
  for (int i = 0; i < 10; ++i) {
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) l(i, col++) = 1.0;
  }
  for (size_t v = 0; v < views.size(); ++v) {
    l.block<6, 6>(10, free + 6 * static_cast<int>(v)) =
        PoseTangentToFrameShare(fit.cam_from_object[v], static_cast<int>(views.size()));
  }
  const double s2 = fit.projection.sigma_px * fit.projection.sigma_px;
  return s2 * l * sigma * l.transpose();
}

// 8 views of kTruth with 0.3 px noise, and the pinhole-k2 refinement's options.
SyntheticBoardViews EightViews(uint64_t seed) {
  SyntheticBoardOptions board;
  board.num_views = 8;
  board.pixel_sigma_px = 0.3;
  Rng rng(seed);
  return MakeBoardViews(kTruth, board, &rng);
}
RefineOptions PinholeK2() {
  RefineOptions options;
  options.model = LensModel::kPinholeK2;
  options.estimate_skew = false;
  return options;
}

TEST(ProjectionUncertainty, SchurCovarianceEqualsTheDenseInverse) {
  const SyntheticBoardViews data = EightViews(11);
  const RefineOptions options = PinholeK2();
  const RefineResult fit = RefineCalibration(data.views, kTruth, data.cam_from_board, options);
  ASSERT_TRUE(fit.IsUsable()) << fit.message;
  ASSERT_TRUE(fit.projection.IsSet());
  const ProjectionCovariance::Matrix dense = DenseCovZ(data.views, fit, options);
  // Two exact inverses of one matrix (Schur complement against dense SVD): rounding only, far
  // below 1e-6 of the largest entry of each block.
  constexpr double kRelTol = 1e-6;
  for (int a = 0; a < 16; ++a) {
    for (int b = 0; b < 16; ++b) {
      const double scale = std::sqrt(dense(a, a) * dense(b, b));
      if (scale == 0) continue;
      EXPECT_NEAR(fit.projection.covariance(a, b), dense(a, b), kRelTol * scale)
          << "z(" << a << ", " << b << ")";
    }
  }
  // The uncertainty map is finite over the image and smallest where the data are dense (the
  // centre), within the same order as sigma / sqrt(points) * a few.
  const UncertaintyMap map = ProjectionUncertaintyMap(fit.intrinsics, fit.projection, 640, 480, {});
  EXPECT_GT(map.median_px, 0.0);
  EXPECT_LT(map.centre_px, map.max_px);
}

TEST(ProjectionUncertainty, AutodiffRefinementGivesTheSameCovariance) {
  const SyntheticBoardViews data = EightViews(12);
  RefineOptions options = PinholeK2();
  const RefineResult analytic = RefineCalibration(data.views, kTruth, data.cam_from_board, options);
  options.autodiff = true;
  const RefineResult jet = RefineCalibration(data.views, kTruth, data.cam_from_board, options);
  ASSERT_TRUE(analytic.projection.IsSet() && jet.projection.IsSet());
  // The same optimum (to ~1e-10) and the same Jacobians: 1e-6 of each entry's scale.
  const ProjectionCovariance::Matrix& a = analytic.projection.covariance;
  for (int r = 0; r < 16; ++r) {
    for (int c = 0; c < 16; ++c) {
      EXPECT_NEAR(jet.projection.covariance(r, c), a(r, c), 1e-6 * std::sqrt(a(r, r) * a(c, c)));
    }
  }
}

// A shared-pose refinement (a scenario's constant extrinsic): Cov(z) two ways from its joint
// covariance. RefineResult::projection maps the quaternion tangent straight to z
// (PoseTangentToFrameShare); ProjectionCovarianceOfEstimate maps the method ceres's 11 x 11 (its
// estimate's covariance, EstimateCovarianceOfSharedPose) through R_C's perturbation in the parent
// frame. Two linear maps of one matrix whose products are algebraically equal: rounding only.
TEST(ProjectionUncertainty, EstimateCovarianceMapsToTheSharedPoseProjectionCovariance) {
  SyntheticBoardOptions board;
  board.num_views = 8;
  board.pixel_sigma_px = 0.3;
  Rng rng(13);
  const CameraIntrinsics pinhole{kTruth.fku_px, kTruth.fkv_px, 90.0, kTruth.u0_px, kTruth.v0_px};
  const SyntheticBoardViews data = MakeBoardViews(pinhole, board, &rng);
  // The boards' points in a parent frame the camera sits in at an arbitrary pose (a rotation
  // away from the identity, and a translation, so that every block of the maps is exercised).
  const Rigid3 cam_from_parent = RandomPose(0.4, &rng);
  std::vector<View> views = data.views;
  for (size_t v = 0; v < views.size(); ++v) {
    const Rigid3 parent_from_board = cam_from_parent.Inverse() * data.cam_from_board[v];
    for (Eigen::Vector3d& x : views[v].points) x = parent_from_board * x;
  }
  RefineOptions options;
  options.model = LensModel::kPinhole;
  options.shared_pose = true;
  options.compute_pose_covariance = true;
  const RefineResult fit = RefineCalibration(views, pinhole, {cam_from_parent}, options);
  ASSERT_TRUE(fit.IsUsable()) << fit.message;
  ASSERT_TRUE(fit.projection.IsSet());
  const Eigen::MatrixXd estimate_covariance =
      EstimateCovarianceOfSharedPose(fit.joint_covariance, fit.cam_from_object[0]);
  ASSERT_EQ(estimate_covariance.rows(), 11);
  ProjectionCovariance mapped;
  ASSERT_TRUE(ProjectionCovarianceOfEstimate(estimate_covariance, fit.cam_from_object[0], &mapped));
  EXPECT_EQ(mapped.num_views, 1);
  // Rounding of a few 3 x 3 products on entries spanning ~8 orders: 1e-9 of each entry's scale.
  constexpr double kRelTol = 1e-9;
  for (int a = 0; a < 16; ++a) {
    for (int b = 0; b < 16; ++b) {
      const double scale =
          std::sqrt(fit.projection.covariance(a, a) * fit.projection.covariance(b, b));
      if (scale == 0) {  // Distortion slots, fixed by the pinhole model: 0 in both.
        EXPECT_EQ(mapped.covariance(a, b), 0.0) << "z(" << a << ", " << b << ")";
        continue;
      }
      EXPECT_NEAR(mapped.covariance(a, b), fit.projection.covariance(a, b), kRelTol * scale)
          << "z(" << a << ", " << b << ")";
    }
  }
  // Not 11 x 11: refused.
  EXPECT_FALSE(ProjectionCovarianceOfEstimate(Eigen::MatrixXd(), cam_from_parent, &mapped));
}

TEST(ProjectionUncertainty, RefusesWithoutCovarianceOrOutsideTheField) {
  PixelUncertainty u;
  std::string why;
  EXPECT_FALSE(ProjectionUncertaintyAt(kTruth, ProjectionCovariance{}, {320, 240},
                                       std::numeric_limits<double>::infinity(), &u, &why));
  EXPECT_NE(why.find("no projection covariance"), std::string::npos) << why;
  ProjectionCovariance c;
  c.num_views = 1;
  EXPECT_FALSE(ProjectionUncertaintyAt(kTruth, c, {320, 240}, -1.0, &u, &why));
  EXPECT_NE(why.find("distance"), std::string::npos) << why;
  // A 190-degree double sphere's image circle ends ~700 px from its centre.
  CameraIntrinsics fisheye;
  fisheye.family = LensFamily::kDoubleSphere;
  fisheye.fku_px = fisheye.fkv_px = 330, fisheye.u0_px = fisheye.v0_px = 512;
  fisheye.xi = -0.2, fisheye.alpha = 0.6;
  EXPECT_FALSE(ProjectionUncertaintyAt(fisheye, c, {2000, 2000},
                                       std::numeric_limits<double>::infinity(), &u, &why));
  EXPECT_NE(why.find("does not unproject"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
