// Regression on published calibration data (CTest label "data"), bundled in data/: Zhang's points
// (data/zhang) and OpenCV's calib1.dat (data/opencv-calib1).
#include "calib/calibrate.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>

#include "calib/calibrate_camera.h"
#include "calib/calibrate_report.h"
#include "io/camera_io.h"
#include "io/points_io.h"
#include "tests/common/test_data.h"
#include "util/random.h"

namespace calibench {
namespace {

// Zhang (MSR-TR-98-71), complete calibration with skew and k1, k2, as published:
// alpha 832.5010, beta 832.5309, gamma 0.2046, u0 303.9584, v0 206.5879, k1 -0.228601,
// k2 0.190353.
TEST(CalibrateFromPoints, ZhangDataMatchesPublishedResults) {
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(BundledData("zhang"), &data, &why)) << why;
  ASSERT_EQ(data.views.size(), 5u);
  ASSERT_EQ(data.views[0].points.size(), 256u);
  CalibrateOptions options;
  options.model = LensModel::kPinholeK2;
  options.estimate_skew = true;
  const CalibrateReport report = CalibrateFromPoints(data, options);
  ASSERT_TRUE(report.IsUsable()) << report.ceres.message;
  const CameraIntrinsics& k = report.ceres.intrinsics;
  // Both solutions minimise the same cost (reprojection, skew + k1, k2) on the same points:
  // Zhang's solver and ceres stop at slightly different points of a flat optimum (the RMS agrees to
  // 1e-4 px). Measured (docs/results/real-data.md): f*ku -1.2e-3, f*kv -1.3e-3, u0 +5e-4,
  // v0 -2.7e-3 px (worst relative 1.3e-5), gamma -1.0e-4, k1 -5e-7, k2 +1.1e-6; the published
  // figures are rounded to 5e-5 px and 5e-7. The bounds are ~4x the worst measured: 0.01 px is
  // 1/65 of the smallest statistical sd (v0 0.66 px), so a moved optimum (one corner of 1280
  // 0.5 px off, a view dropped, a half-pixel convention) fails it. Absolute px: a relative bound on
  // u0 and v0 would depend on where the pixel origin is. (The issue asked for 0.1 % and 1 %: far
  // looser.)
  constexpr double kPublishedAgreementPx = 0.01, kGammaTol = 5e-4, kDistortionTol = 5e-6;
  EXPECT_NEAR(k.fku_px, 832.5010, kPublishedAgreementPx);
  EXPECT_NEAR(k.fkv_px, 832.5309, kPublishedAgreementPx);
  EXPECT_NEAR(k.u0_px, 303.9584, kPublishedAgreementPx);
  EXPECT_NEAR(k.v0_px, 206.5879, kPublishedAgreementPx);
  const double gamma = k.Matrix()(0, 1);  // Zhang's skew term.
  EXPECT_NEAR(gamma, 0.2046, kGammaTol);
  EXPECT_NEAR(k.k1, -0.228601, kDistortionTol);
  EXPECT_NEAR(k.k2, 0.190353, kDistortionTol);
  // SOURCE.md: the published calibration reprojects with 0.3364 px RMS per point.
  EXPECT_NEAR(report.ceres.rms_reproj_px, 0.3364, 0.001);
  EXPECT_TRUE(std::isfinite(report.ceres.intrinsics_std[0]));
  // Mutation checked: data.views[2].pixels[100].x() += 0.5 moves f*ku by 0.013 px, f*kv by 0.013,
  // k1 by 2e-4: fails here (the RMS check and the old 1e-3 relative bound both pass it).
}

// One view of Zhang's points replaced by pixels that belong to no board (a wrong file in the
// folder): the start goes wrong (zhang's f comes out ~0.6 px) and Ceres cannot evaluate the
// start. The failure is one line that names the view's file and the reason.
TEST(CalibrateFromPoints, AFailureNamesTheViewItIsTracedTo) {
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(BundledData("zhang"), &data, &why)) << why;
  ASSERT_EQ(data.view_names.size(), data.views.size());
  EXPECT_EQ(data.view_names[2], "data3.txt");
  Rng rng(7);
  for (Eigen::Vector2d& pixel : data.views[2].pixels) {
    const double v = rng.Uniform(0, 480);  // Last first (util/random.h).
    pixel = Eigen::Vector2d(rng.Uniform(0, 640), v);
  }
  CalibrateOptions options;
  options.model = LensModel::kPinholeK2;
  const CalibrateReport report = CalibrateFromPoints(data, options);
  ASSERT_FALSE(report.IsUsable());
  ASSERT_EQ(report.zhang.used_views.size(), 5u);  // So ceres' view 2 is the data's view 2.
  EXPECT_EQ(report.ceres.failed_view, 2);
  EXPECT_NE(report.ceres.message.find("data3.txt: "), std::string::npos) << report.ceres.message;
  EXPECT_EQ(report.ceres.message.find('\n'), std::string::npos) << report.ceres.message;
}

// OpenCV's regression file carries Bouguet's toolbox results (k1 k2 p1 p2 model).
TEST(CalibrateFromPoints, OpenCvCalib1MatchesItsReference) {
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(BundledData("opencv-calib1/calib1.dat"), &data, &why)) << why;
  ASSERT_EQ(data.views.size(), 7u);
  ASSERT_TRUE(data.reference.has_value());
  CalibrateOptions options;
  options.model = LensModel::kPinholeRadTan4;
  const CalibrateReport report = CalibrateFromPoints(data, options);
  ASSERT_TRUE(report.IsUsable()) << report.ceres.message;
  const CameraIntrinsics &k = report.ceres.intrinsics, &ref = *data.reference;
  // The file prints 8 significant digits for A and 5 decimals for distortion.
  EXPECT_NEAR(k.fku_px, ref.fku_px, 1e-5 * ref.fku_px);
  EXPECT_NEAR(k.fkv_px, ref.fkv_px, 1e-5 * ref.fkv_px);
  EXPECT_NEAR(k.u0_px, ref.u0_px, 1e-5 * ref.u0_px);
  EXPECT_NEAR(k.v0_px, ref.v0_px, 1e-5 * ref.v0_px);
  for (const auto& [ours, theirs] :
       {std::pair{k.k1, ref.k1}, {k.k2, ref.k2}, {k.p1, ref.p1}, {k.p2, ref.p2}}) {
    EXPECT_NEAR(ours, theirs, 1e-4);
  }
  // Ceres and OpenCV minimise the same cost: the same optimum.
  EXPECT_NEAR(k.fku_px, report.zhang.intrinsics.fku_px, 1e-3);
}

// The jackknife std of calibrate (AddJackknife: each view left out in turn, refined from the full
// fit) against the same formula over five calibrations each run from scratch (zhang + ceres) on
// the other four views: the same optima, so the same std to the solvers' convergence
// (kSameOptimumPx: 1e-3 px on a std of ~5 px; the solver's tolerances are 1e-10, refine.cc).
TEST(CalibrateFromPoints, JackknifeIsTheSpreadOfCalibrationsLeavingOneViewOut) {
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(BundledData("zhang"), &data, &why)) << why;
  CalibrateOptions options;
  options.model = LensModel::kPinholeK2;
  options.estimate_skew = true;
  CalibrateReport report = CalibrateFromPoints(data, options);
  ASSERT_TRUE(report.IsUsable()) << report.ceres.message;
  AddJackknife(data, options, &report);  // kAuto: 5 views <= kJackknifeAutoMaxViews.
  ASSERT_TRUE(report.jackknife && report.jackknife->IsUsable());
  const int n = static_cast<int>(data.views.size());
  std::vector<double> fku;
  for (int left_out = 0; left_out < n; ++left_out) {
    PointData rest = data;
    rest.views.erase(rest.views.begin() + left_out);
    const CalibrateReport refit = CalibrateFromPoints(rest, options);
    ASSERT_TRUE(refit.IsUsable()) << refit.ceres.message;
    fku.push_back(refit.ceres.intrinsics.fku_px);
  }
  double mean = 0, sum_sq = 0;
  for (double f : fku) mean += f / n;
  for (double f : fku) sum_sq += (f - mean) * (f - mean);
  constexpr double kSameOptimumPx = 1e-3;
  EXPECT_NEAR(report.jackknife->intrinsics_std[0], std::sqrt((n - 1.0) / n * sum_sq),
              kSameOptimumPx);
  // Zhang's five views disagree more than their residuals say (measured: 4.9 px against the
  // formal 1.4 px): the report warns.
  EXPECT_GT(report.jackknife->intrinsics_std[0],
            kJackknifeFlagRatio * report.ceres.intrinsics_std[0]);
  EXPECT_NE(FormatCalibrateReport(report, data).find("warning: the jackknife std exceeds"),
            std::string::npos);
  options.jackknife = CalibrateOptions::Jackknife::kOff;
  AddJackknife(data, options, &report);
  EXPECT_FALSE(report.jackknife.has_value());
  EXPECT_EQ(FormatCalibrateReport(report, data).find("jackknife"), std::string::npos);
}

TEST(CalibrateFromPoints, CameraYamlIsReadableByOpenCv) {
  CameraFile camera;
  camera.intrinsics = {800, 790, 89, 320, 240, -0.1, 0.02, 1e-3, -1e-3, 0.0};
  camera.intrinsics_std.fill(std::nan(""));
  camera.intrinsics_std[0] = 1.5;
  camera.image_width = 640;
  camera.image_height = 480;
  camera.rms_reproj_px = 0.25;
  camera.lens_model = LensModel::kPinholeRadTan4;
  camera.estimate_skew = true;
  const std::string path = ::testing::TempDir() + "/camera.yaml";
  std::string why;
  ASSERT_TRUE(WriteCameraFile(path, CameraFormat::kOpenCv, camera, &why)) << why;
  cv::FileStorage fs(path, cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  cv::Mat a, d;
  fs["camera_matrix"] >> a;
  fs["distortion_coefficients"] >> d;
  EXPECT_NEAR(a.at<double>(0, 0), 800, 1e-9);
  EXPECT_NEAR(a.at<double>(0, 1), camera.intrinsics.Matrix()(0, 1), 1e-9);
  EXPECT_NEAR(d.at<double>(2), 1e-3, 1e-15);
  EXPECT_EQ(static_cast<int>(fs["image_width"]), 640);
  EXPECT_EQ(static_cast<double>(fs["rms_reproj_px"]), 0.25);
  EXPECT_EQ(static_cast<double>(fs["std_fku_px"]), 1.5);
  EXPECT_TRUE(fs["std_fkv_px"].empty());  // Not estimated: not written.
}

// calibrate --init: a calibration written in each format and read back evaluates to the same
// per-view RMS on the same data (the poses re-found through the camera reach the same optimum),
// and refining from it lands on the same intrinsics.
// The RMS at an optimum is flat in the parameters: 1e-6 px. The parameters themselves settle to a
// small fraction of their standard deviation (ceres' relative cost tolerance 1e-10, refine.cc):
// 1e-3 sigma.
constexpr double kSameOptimumRmsPx = 1e-6;
constexpr double kSameOptimumSigmas = 1e-3;

TEST(CalibrateFromPoints, AGivenCameraInEveryFormatEvaluatesAndRefinesToTheSameOptimum) {
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(BundledData("zhang"), &data, &why)) << why;
  CalibrateOptions options;
  options.model = LensModel::kPinholeRadTan4;  // Every format holds it.
  const CalibrateReport first = CalibrateFromPoints(data, options);
  ASSERT_TRUE(first.IsUsable()) << first.ceres.message;
  for (const char* file : {"init.yaml", "init-camchain.yaml", "init.cameramodel"}) {
    const std::string path = ::testing::TempDir() + "/" + file;
    ASSERT_TRUE(WriteCameraFile(path, CameraFormatFromPath(path), first.camera, &why)) << why;
    CameraFile given;
    ASSERT_TRUE(ReadCameraFile(path, &given, &why)) << why;
    EXPECT_EQ(given.lens_model, LensModel::kPinholeRadTan4) << file;
    CalibrateOptions evaluate;
    evaluate.model = given.lens_model;
    evaluate.init = given;
    evaluate.evaluate_only = true;
    const CalibrateReport evaluated = CalibrateFromPoints(data, evaluate);
    ASSERT_TRUE(evaluated.IsUsable()) << evaluated.ceres.message;
    EXPECT_TRUE(evaluated.evaluated);
    EXPECT_EQ(evaluated.ceres.intrinsics, given.intrinsics) << "kept fixed";
    ASSERT_EQ(evaluated.ceres.view_rms_px.size(), first.ceres.view_rms_px.size());
    for (size_t v = 0; v < first.ceres.view_rms_px.size(); ++v) {
      EXPECT_NEAR(evaluated.ceres.view_rms_px[v], first.ceres.view_rms_px[v], kSameOptimumRmsPx)
          << file << " view " << v;
    }
    CalibrateOptions refine = evaluate;
    refine.evaluate_only = false;
    const CalibrateReport refined = CalibrateFromPoints(data, refine);
    ASSERT_TRUE(refined.IsUsable()) << refined.ceres.message;
    const auto a = refined.ceres.intrinsics.Params(), b = first.ceres.intrinsics.Params();
    for (int i = 0; i < 10; ++i) {
      const double sigma = first.ceres.intrinsics_std[i];
      EXPECT_NEAR(a[i], b[i], std::isfinite(sigma) ? kSameOptimumSigmas * sigma : 0.0)
          << file << " " << ParamNames(LensFamily::kRadTan)[i];
    }
  }
}

// Options that fail Check are refused before any fit, and the report says so in one line (the
// library's users print it as the CLI does).
TEST(CalibratePoints, OptionsThatFailCheckAreRefusedInOneLine) {
  PointData data;
  std::string why;
  ASSERT_TRUE(LoadPointData(BundledData("zhang"), &data, &why)) << why;
  CalibrateOptions options;
  options.evaluate_only = true;  // Without init: nothing to evaluate.
  const CalibrateResult result = CalibratePoints(data, options);
  EXPECT_FALSE(result.IsUsable());
  EXPECT_EQ(FormatCalibrateReport(result),
            "calibration refused: evaluate_only needs init (the calibration to evaluate)\n");
  options.evaluate_only = false;
  const CalibrateResult fitted = CalibratePoints(data, options);
  ASSERT_TRUE(fitted.IsUsable()) << fitted.message;
  EXPECT_EQ(FormatCalibrateReport(fitted).rfind("data: ", 0), 0u);  // The full report.
}

TEST(LoadPointData, BadPathsAreNamed) {
  PointData data;
  std::string why;
  EXPECT_FALSE(LoadPointData("/nonexistent/points", &data, &why));
  EXPECT_NE(why.find("/nonexistent/points"), std::string::npos);
  const std::string empty_dir = ::testing::TempDir() + "/empty_points";
  std::filesystem::create_directories(empty_dir);
  EXPECT_FALSE(LoadPointData(empty_dir, &data, &why));
  EXPECT_NE(why.find("Model.txt"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
