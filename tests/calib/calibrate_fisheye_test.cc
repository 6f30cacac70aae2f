// The equidistant fisheye (pinhole-equi) end to end: our projection against cv::fisheye's, and
// `calibrate --images --model pinhole-equi` on rendered fisheye frames against the truth and
// against cv::fisheye::calibrate on the same corners.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>

#include "calib/calibrate.h"
#include "calib/calibrate_report.h"
#include "calib/image_points.h"
#include "io/target_io.h"
#include "tests/common/rendered_folder.h"

namespace calibench {
namespace {

// A 640 x 480 fisheye of 300 px focal length (about 75 degrees from the axis at the corners),
// with Kannala-Brandt terms of the size real lenses have.
CameraIntrinsics FisheyeTruth() {
  CameraIntrinsics k;
  k.family = LensFamily::kEquidistant;
  k.fku_px = 300.0, k.fkv_px = 300.6, k.u0_px = 321.3, k.v0_px = 242.7;
  k.k1 = -0.02, k.k2 = 0.01, k.k3 = -0.003, k.k4 = 0.0004;
  return k;
}

// cv::fisheye::projectPoints evaluates the same model independently (its own theta polynomial
// and distortion scaling, in double): the two agree to rounding of values ~1e3 px, ~1e-13 px
// (measured 1.7e-13); 1e-9 px leaves room for another libm, not for another model.
constexpr double kSameModelPx = 1e-9;

TEST(Fisheye, ProjectionEqualsCvFisheyeProjectPoints) {
  const CameraIntrinsics k = FisheyeTruth();
  std::vector<cv::Point3d> points;
  for (double x = -2.0; x <= 2.0; x += 0.25) {
    for (double y = -1.5; y <= 1.5; y += 0.25) points.emplace_back(x, y, 1.0);
  }
  const cv::Matx33d camera_matrix(k.fku_px, 0, k.u0_px, 0, k.fkv_px, k.v0_px, 0, 0, 1);
  const cv::Vec4d dist(k.k1, k.k2, k.k3, k.k4);
  std::vector<cv::Point2d> theirs;
  cv::fisheye::projectPoints(points, theirs, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix,
                             dist);
  double max_diff = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d ours;
    ASSERT_TRUE(ProjectPoint(k, Eigen::Vector3d(points[i].x, points[i].y, points[i].z), &ours));
    max_diff =
        std::max({max_diff, std::abs(ours.x() - theirs[i].x), std::abs(ours.y() - theirs[i].y)});
    EXPECT_NEAR(ours.x(), theirs[i].x, kSameModelPx);
    EXPECT_NEAR(ours.y(), theirs[i].y, kSameModelPx);
  }
  std::cout << "max |ours - cv::fisheye| = " << max_diff << " px\n";
}

// The bars: f within 0.1 %, the principal point within 0.5 px, each k within 3 reported
// standard deviations.
constexpr double kFocalRelTol = 1e-3;
constexpr double kCentreTolPx = 0.5;
constexpr double kSigmas = 3.0;

TEST(Fisheye, CalibrateImagesRecoversARenderedFisheyeAndAgreesWithCvFisheye) {
  const CameraIntrinsics truth = FisheyeTruth();
  AprilGrid grid;
  grid.tag_size_m = 0.07;
  grid.black_tag_border = 2;  // As Kalibr prints it (the target YAML's default).
  RenderedFolderOptions options;
  options.views = 20;
  options.lateral_m = 0.2;  // Boards across the image: the distortion needs large angles.
  const std::string dir = ::testing::TempDir() + "/fisheye_views";
  ASSERT_EQ(WriteRenderedAprilGridFolder(dir, truth, grid, options), options.views);
  const std::string target_path = ::testing::TempDir() + "/fisheye_target.yaml";
  std::ofstream(target_path) << "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 6\n"
                                "tagSize: 0.07\ntagSpacing: 0.3\n"
                                "cornerSquares: false\n";
  CalibrationTarget target;
  std::string why;
  ASSERT_TRUE(LoadTargetYaml(target_path, &target, &why)) << why;
  PointData data;
  ImageFolderReport images;
  std::vector<int> used;
  ASSERT_TRUE(LoadImagePoints(dir, target, &data, &images, &used, &why,
                              {LensFamily::kEquidistant, std::nullopt, std::nullopt}))
      << why;
  EXPECT_EQ(images.used, options.views);
  CalibrateOptions calibrate;
  calibrate.model = LensModel::kPinholeEqui;
  const CalibrateReport report = CalibrateFromPoints(data, calibrate);
  ASSERT_TRUE(report.IsUsable()) << report.ceres.message;
  const CameraIntrinsics& k = report.ceres.intrinsics;
  ASSERT_EQ(k.family, LensFamily::kEquidistant);
  std::cout << FormatCalibrateReport(report, data);
  EXPECT_NEAR(k.fku_px, truth.fku_px, kFocalRelTol * truth.fku_px);
  EXPECT_NEAR(k.fkv_px, truth.fkv_px, kFocalRelTol * truth.fkv_px);
  EXPECT_NEAR(k.u0_px, truth.u0_px, kCentreTolPx);
  EXPECT_NEAR(k.v0_px, truth.v0_px, kCentreTolPx);
  const auto est = k.Params(), want = truth.Params();
  // And unbiased: every free parameter within 3 sigma (the straight-edge corner fit, which a
  // fisheye bends, put f 32 sigma low on these frames; corner_refinement.h, curved_edges).
  for (int i : {0, 1, 3, 4}) {
    EXPECT_NEAR(est[i], want[i], kSigmas * report.ceres.intrinsics_std[i])
        << ParamNames(k.family)[i];
  }
  for (int i = 5; i < 9; ++i) {
    const double sigma = report.ceres.intrinsics_std[i];
    ASSERT_TRUE(std::isfinite(sigma)) << ParamNames(k.family)[i];
    EXPECT_NEAR(est[i], want[i], kSigmas * sigma) << ParamNames(k.family)[i];
  }
  // cv::fisheye::calibrate (the initialisation) on the same corners minimises the same
  // reprojection error with fixed skew: the same optimum, to far below the uncertainty.
  const CameraIntrinsics& cv_k = report.zhang.intrinsics;
  ASSERT_EQ(cv_k.family, LensFamily::kEquidistant);
  const auto cv_p = cv_k.Params();
  for (int i : {0, 1, 3, 4, 5, 6, 7, 8}) {
    const double sigma = report.ceres.intrinsics_std[i];
    EXPECT_NEAR(cv_p[i], est[i], 0.1 * sigma) << ParamNames(k.family)[i] << " vs cv::fisheye";
  }
  EXPECT_NEAR(report.zhang.rms_reproj_px, report.ceres.rms_reproj_px, 1e-3);
}

}  // namespace
}  // namespace calibench
