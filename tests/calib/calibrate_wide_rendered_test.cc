// calibrate --images through rendered 190 and 160 degree lenses of every wide family: Kalibr's
// printed AprilGrid (6 x 6 tags) rendered through the truth (sim/render.h) in 20 views, written
// as PNG files, detected (LoadImagePoints: curved tag edges), calibrated (CalibrateFromPoints: the
// wide start, then ceres) and the corners re-fitted through the estimate
// (IterateCornersThroughTheLens), as `calibrate --images --model M` does. Every estimated
// intrinsic is compared with the truth in units of its reported std; a cross-fit fits one
// family's corners with another and reports the projection difference over the image.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <vector>

#include "calib/calibrate.h"
#include "calib/image_points.h"
#include "sim/render.h"
#include "sim/synthetic.h"
#include "tests/common/calibrate_folder.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kSide = 800;                      // The images: 800 x 800.
constexpr double kFieldCircleRadiusPx = 380.0;  // Where the lens's half field lands.
constexpr int kViews = 20;

struct WideTruth {
  std::string name;
  LensModel model;
  CameraIntrinsics camera;
  double field_deg;
};

// `k`'s lens with its half field on the field circle, the principal point off the centre.
WideTruth MakeTruth(LensModel model, CameraIntrinsics k, double field_deg) {
  const double f = FocalLengthPuttingRayAt(k, field_deg / 2, kFieldCircleRadiusPx);
  k.fku_px = f, k.fkv_px = 1.002 * f;
  k.u0_px = 401.7, k.v0_px = 397.6;
  char name[64];
  std::snprintf(name, sizeof(name), "%s %.0f deg", ToString(model), field_deg);
  return {name, model, k, field_deg};
}

// The truths: every omnidirectional family at 190 and 160 deg, and pinhole-equi (which projects
// only in front: Z > 0) at 160 deg. The 190 deg eucm has beta = 1: it is the unified lens with
// xi = alpha / (1 - alpha) = 1.5 and no distortion (the cross-fit's equivalent pair).
std::vector<WideTruth> Truths() {
  CameraIntrinsics unified;
  unified.family = LensFamily::kUnified;
  unified.xi = 0.9, unified.k1 = -0.05, unified.k2 = 0.005, unified.p1 = 3e-4, unified.p2 = -2e-4;
  CameraIntrinsics eucm;
  eucm.family = LensFamily::kEucm;
  eucm.alpha = 0.6, eucm.beta = 1.0;
  CameraIntrinsics eucm160 = eucm;
  eucm160.alpha = 0.55, eucm160.beta = 1.15;
  CameraIntrinsics ds;
  ds.family = LensFamily::kDoubleSphere;
  ds.xi = -0.15, ds.alpha = 0.6;
  CameraIntrinsics ds160 = ds;
  ds160.xi = 0.1, ds160.alpha = 0.55;
  CameraIntrinsics equi;
  equi.family = LensFamily::kEquidistant;
  equi.k1 = 0.02, equi.k2 = -0.01, equi.k3 = 0.003, equi.k4 = -5e-4;
  return {
      MakeTruth(LensModel::kUnified, unified, 190),   MakeTruth(LensModel::kEucm, eucm, 190),
      MakeTruth(LensModel::kDoubleSphere, ds, 190),   MakeTruth(LensModel::kPinholeEqui, equi, 160),
      MakeTruth(LensModel::kUnified, unified, 160),   MakeTruth(LensModel::kEucm, eucm160, 160),
      MakeTruth(LensModel::kDoubleSphere, ds160, 160)};
}

// Kalibr's grid of the shared TUM VI / EuRoC targets: 6 x 6 tag36h11, tag 8.8 cm, spacing 0.3,
// the corner squares printed.
AprilGrid KalibrGrid() {
  AprilGrid grid;
  grid.tag_size_m = 0.088;
  grid.black_tag_border = 2;
  grid.corner_squares = true;
  return grid;
}
constexpr const char* kKalibrTargetYaml =
    "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 6\ntagSize: 0.088\ntagSpacing: 0.3\n";

// Every corner of the grid projects (kInsidePx inside the image) for the view to count whole;
// a view is kept when at least kMinCornersIn of the 144 corners do (boards at the image circle's
// edge are partial).
bool CornersIn(const AprilGrid& grid, const CameraIntrinsics& k, const Rigid3& pose, int* in) {
  constexpr double kInsidePx = 6.0;
  *in = 0;
  for (const Eigen::Vector3d& p : grid.CornersInBoard()) {
    Eigen::Vector2d px;
    *in += ProjectPoint(k, pose * p, &px) && px.x() > kInsidePx && px.y() > kInsidePx &&
           px.x() < kSide - 1 - kInsidePx && px.y() < kSide - 1 - kInsidePx;
  }
  return *in > 0;
}
constexpr int kMinCornersIn = 80;

// Writes kViews PNG frames of the grid seen through `truth` into `dir`: board centres spread from
// the axis to 8 deg inside the half field (past 90 deg on the 190 deg lenses), tilted up to 35
// deg, 0.3-0.45 m away; blur 0.8 px (computed on a 2x grid), 2 gray levels of noise.
int WriteFrames(const WideTruth& truth, const std::string& dir, uint64_t seed) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const AprilGrid grid = KalibrGrid();
  const auto family = TagFamily::Create(grid.family, grid.black_tag_border, nullptr);
  RenderOptions ro;
  ro.width = ro.height = kSide;
  ro.blur_sigma_px = 0.8;
  ro.blur_grid = 2;
  ro.noise_sigma_gray = 2.0;
  std::string why;
  const auto renderer = FrameRenderer::Create(truth.camera, ro, &why);
  EXPECT_TRUE(renderer) << why;
  if (!renderer || !family) return 0;
  const double extent = 5 * grid.Pitch() + grid.tag_size_m;
  const Eigen::Vector3d centre(extent / 2, extent / 2, 0);
  Rng rng(seed);
  int written = 0;
  for (int v = 0; v < kViews; ++v) {
    const double angle = (truth.field_deg / 2 - 8) * std::sqrt((v + 0.5) / kViews);
    for (int attempt = 0; attempt < 300; ++attempt) {
      const Rigid3 pose = RandomFacingBoardPose(centre, angle, {35, 0.3, 0.45}, &rng);
      int in = 0;
      CornersIn(grid, truth.camera, pose, &in);
      if (in < kMinCornersIn) continue;
      GrayImage image;
      if (!renderer->Render({{grid, family, pose}}, &rng, &image, &why)) break;
      const cv::Mat mat(image.height, image.width, CV_8UC1, image.pixels.data());
      char name[32];
      std::snprintf(name, sizeof(name), "/view%02d.png", v);
      if (cv::imwrite(dir + name, mat)) ++written;
      break;
    }
  }
  return written;
}

struct Fit {
  CalibrateReport report;
  PointData data;
  int views_used = 0;
  double seconds = 0;
};

// calibrate --images DIR --target (Kalibr grid) --model M: detection with curved edges, the
// calibration, then the re-fits of the corners through the estimate, as many as calibrate's
// default allows (--corner-iterations).
Fit CalibrateImages(const std::string& dir, LensModel model) {
  const auto start = std::chrono::steady_clock::now();
  Fit fit;
  CalibrationTarget target;
  std::string why;
  EXPECT_TRUE(LoadTargetYaml(WriteTarget("kalibr_grid.yaml", kKalibrTargetYaml), &target, &why))
      << why;
  const FolderCalibration c = CalibrateFolderThroughTheLens(dir, target, model);
  std::printf("%s", c.log.c_str());
  fit.data = c.last.data;
  fit.report = c.last.report;
  fit.views_used = c.last.images.used;
  fit.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return fit;
}

// The projection difference of `fitted` against `truth` over the image: pixels on a 8 px grid
// inside the image whose truth ray is within the truth's half field, lifted through the truth and
// projected through the fitted camera (both in their own frames).
struct ProjectionDiff {
  double rms_px = 0, max_px = 0;
  int pixels = 0, unprojectable = 0;
};
ProjectionDiff CompareProjection(const CameraIntrinsics& truth, const CameraIntrinsics& fitted,
                                 double half_field_deg) {
  ProjectionDiff d;
  double sum2 = 0;
  for (int y = 4; y < kSide; y += 8) {
    for (int x = 4; x < kSide; x += 8) {
      Eigen::Vector3d ray;
      const Eigen::Vector2d pixel(x, y);
      if (!UnprojectToRay(truth, pixel, &ray)) continue;
      if (std::acos(ray.normalized().z()) > half_field_deg * kDeg) continue;
      Eigen::Vector2d back;
      if (!ProjectPoint(fitted, ray, &back)) {
        ++d.unprojectable;
        continue;
      }
      const double e = (back - pixel).norm();
      sum2 += e * e;
      d.max_px = std::max(d.max_px, e);
      ++d.pixels;
    }
  }
  if (d.pixels > 0) d.rms_px = std::sqrt(sum2 / d.pixels);
  return d;
}

// The free intrinsics' errors in units of their reported std (z) and the Mahalanobis distance of
// the error vector under the reported covariance (d2, chi-square with `free` degrees of freedom
// when the covariance is right and the estimate unbiased).
struct Consistency {
  double max_abs_z = 0;
  std::string worst;
  int free = 0, beyond_2_std = 0;
  double d2 = NAN;
};
Consistency CheckAgainstTruth(const WideTruth& truth, const RefineResult& r) {
  Consistency c;
  const std::vector<int> fixed = FixedIntrinsics(truth.model, false);
  const auto est = r.intrinsics.Params(), tru = truth.camera.Params();
  std::vector<int> free;
  for (int i = 0; i < 10; ++i) {
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) free.push_back(i);
  }
  c.free = static_cast<int>(free.size());
  Eigen::VectorXd e(c.free);
  Eigen::MatrixXd cov(c.free, c.free);
  for (int a = 0; a < c.free; ++a) {
    e[a] = est[free[a]] - tru[free[a]];
    for (int b = 0; b < c.free; ++b) cov(a, b) = r.covariance(free[a], free[b]);
    const double z = e[a] / r.intrinsics_std[free[a]];
    std::printf("    %-6s truth %12.6g  estimate %12.6g  std %10.3g  z %+6.2f\n",
                ParamNames(truth.camera.family)[free[a]], tru[free[a]], est[free[a]],
                r.intrinsics_std[free[a]], z);
    c.beyond_2_std += !(std::abs(z) <= 2.0);
    if (!(std::abs(z) <= c.max_abs_z)) {
      c.max_abs_z = std::abs(z);
      c.worst = ParamNames(truth.camera.family)[free[a]];
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(cov);
  c.d2 = e.dot(ldlt.solve(e));
  return c;
}

// Measured (20 views each, the corners re-fitted through the estimate until f.ku settles: 2-3
// passes; RMS 0.0042-0.0051 px): the fitted camera projects every ray of the field within
// 0.0009-0.0031 px of the truth (max over the field), and 47 of the 50 free intrinsics lie
// within 2 reported std of the truth on the test's frames: eucm 160's alpha and beta at -3.10 and
// +2.71 (nearly collinear: one error direction; Mahalanobis d2 13.1 for 6 dof), eucm 190's alpha
// at -2.06. A 95% interval expects 2.5 of 50 beyond. With a single pass (the corners fitted once
// through the first, homography-based estimate, f.ku 3 px off on unified 190) up to 4.6 std: the
// passes matter.
// Over 6 frame sets (CALIBENCH_WIDE_SEED=0..5; docs/results/wide-lenses.md) 17 of 300 intrinsics
// lie beyond 2 std (13.7 expected) and d2 ranges 1.1-25.1: the covariance is right. (Before the
// renderer's finer grid took cubic rather than bilinear corner rays, pinhole-equi 160 deg's
// k1..k4 were off by up to 4.4 std with d2 105-181: the renderer's edges, not the detector's.)
//
// Tolerances: kStdUnits, the "within 2 reported std" of the family's acceptance, bounds every
// parameter but kMaxBeyond2Std per truth (2: one correlated pair leaves together, as measured;
// unified's f, xi and k1 move as one, and on 2 of the 6 frame sets 4-5 of its 9 left together at
// d2 7.7 and 24.4); kMaxAbsZ bounds all of them (P(|z| > 4) = 6e-5 for a right covariance); the
// Mahalanobis d2 is bounded by the chi-square quantile of probability 0.9999 for the free
// parameters (Wilson-Hilferty: 32 for 8 dof). kTruthProjectionPx bounds the projection difference
// to the truth over the field: 2x the corners' RMS (a calibration whose projection is off by more
// than twice its data's noise anywhere is wrong).
//
// kEquivalentDiffPx: the cross-fit of an equivalent pair (eucm with beta = 1 is unified without
// distortion) differs by the fit's noise only: measured 0.0012 px max over the image, as the own
// family's fit; 0.02 px is several times that.
//
// Cross-fits of families that are not equivalent (measured, reported only): double-sphere 190 deg
// by eucm 0.029 px max (fit RMS 0.012 px against 0.005 px); unified 160 deg (radtan on the
// sphere) by double-sphere 0.38 px max; pinhole-equi 160 deg by double-sphere 0.12 px max.
constexpr double kStdUnits = 2.0;
constexpr int kMaxBeyond2Std = 2;
constexpr double kMaxAbsZ = 4.0;
constexpr double kTruthProjectionPx = 0.01;
constexpr double kEquivalentDiffPx = 0.02;
constexpr double kD2ProbabilityZ = 3.719;  // The normal quantile of probability 0.9999.

// The chi-square quantile (Wilson-Hilferty) of `dof` degrees of freedom at kD2ProbabilityZ.
double ChiSquareQuantile(int dof) {
  const double k = dof, a = 2.0 / (9.0 * k);
  return k * std::pow(1 - a + kD2ProbabilityZ * std::sqrt(a), 3);
}

// A truth, and optionally another model fitted to its corners (the cross-fit).
struct Case {
  size_t truth;
  std::optional<LensModel> cross;
  bool equivalent = false;
};

class CalibrateWideRendered : public testing::TestWithParam<Case> {};

TEST_P(CalibrateWideRendered, EveryIntrinsicWithinItsStdOfTheTruth) {
  const Case& test = GetParam();
  const WideTruth truth = Truths()[test.truth];
  const std::string dir =
      testing::TempDir() + "/calibrate_wide_rendered_" + std::to_string(test.truth);
  // CALIBENCH_WIDE_SEED (default 0) draws other frames: the over-seeds study of
  // docs/results/wide-lenses.md runs the suite with 0..5.
  const char* seed_env = std::getenv("CALIBENCH_WIDE_SEED");
  const uint64_t seed =
      100 + test.truth + 1000 * (seed_env ? std::strtoull(seed_env, nullptr, 10) : 0);
  ASSERT_EQ(WriteFrames(truth, dir, seed), kViews) << truth.name;
  const Fit fit = CalibrateImages(dir, truth.model);
  ASSERT_TRUE(fit.report.IsUsable()) << truth.name << ": " << fit.report.ceres.message;
  std::printf("%s: %d views, %d points, RMS %.4f px, %.1f s\n", truth.name.c_str(), fit.views_used,
              fit.report.ceres.num_points, fit.report.ceres.rms_reproj_px, fit.seconds);
  const Consistency c = CheckAgainstTruth(truth, fit.report.ceres);
  std::printf("  max |z| %.2f (%s), %d of %d beyond %.0f std, Mahalanobis d2 %.1f (%d dof)\n",
              c.max_abs_z, c.worst.c_str(), c.beyond_2_std, c.free, kStdUnits, c.d2, c.free);
  const double half_field = truth.field_deg / 2;
  const ProjectionDiff own =
      CompareProjection(truth.camera, fit.report.camera.intrinsics, half_field);
  std::printf("  projection difference to the truth over the field: RMS %.4f px, max %.4f px\n",
              own.rms_px, own.max_px);
  EXPECT_EQ(fit.views_used, kViews);
  EXPECT_EQ(own.unprojectable, 0);
  EXPECT_LT(own.max_px, kTruthProjectionPx);
  EXPECT_LE(c.beyond_2_std, kMaxBeyond2Std);
  EXPECT_LT(c.max_abs_z, kMaxAbsZ) << c.worst;
  EXPECT_LT(c.d2, ChiSquareQuantile(c.free));
  if (test.cross) {
    CalibrateOptions options;
    options.model = *test.cross;
    const CalibrateReport r = CalibrateFromPoints(fit.data, options);
    ASSERT_TRUE(r.IsUsable()) << "by " << ToString(*test.cross) << ": " << r.ceres.message;
    const ProjectionDiff d = CompareProjection(truth.camera, r.camera.intrinsics, half_field);
    std::printf(
        "  cross-fit by %s: RMS %.4f px (own family %.4f px); projection difference over the "
        "field: RMS %.4f px, max %.4f px (own family: %.4f, %.4f) on %d pixels\n",
        ToString(*test.cross), r.ceres.rms_reproj_px, fit.report.ceres.rms_reproj_px, d.rms_px,
        d.max_px, own.rms_px, own.max_px, d.pixels);
    EXPECT_EQ(d.unprojectable, 0);
    if (test.equivalent) {
      EXPECT_LT(d.max_px, kEquivalentDiffPx);
    }
  }
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Lenses, CalibrateWideRendered,
                         testing::Values(Case{0, std::nullopt}, Case{1, LensModel::kUnified, true},
                                         Case{2, LensModel::kEucm},
                                         Case{3, LensModel::kDoubleSphere},
                                         Case{4, LensModel::kDoubleSphere}, Case{5, std::nullopt},
                                         Case{6, std::nullopt}),
                         [](const testing::TestParamInfo<Case>& param) {
                           std::string name = Truths()[param.param.truth].name;
                           for (char& ch : name) {
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace calibench
