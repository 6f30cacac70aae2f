// The wide start (batch/wide_init.h) and the refinement of the wide families from it, on synthetic
// 160 and 190 degree lenses of every wide family (sim/synthetic.h, MakeWideBoardViews: 20 views
// of a planar board anywhere in the field, partial boards at the image circle's edge, 0.2 px).
#include "batch/wide_init.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "batch/refine.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr int kImageSide = 1024;
constexpr double kCircleRadiusPx = 490;  // The half field of view lands here.
constexpr double kNoisePx = 0.2;

// The image radius of a ray at `theta` from the axis before A (a unit focal length); equidistant
// past 90 deg by its polynomial, which the model stops using at 90.
double NormalisedRadius(const CameraIntrinsics& shape, double theta) {
  if (shape.family == LensFamily::kEquidistant) {
    const double t2 = theta * theta;
    return theta * (1 + t2 * (shape.k1 + t2 * (shape.k2 + t2 * (shape.k3 + t2 * shape.k4))));
  }
  CameraIntrinsics unit = shape;
  unit.fku_px = unit.fkv_px = 1, unit.u0_px = unit.v0_px = 0, unit.phi_deg = 90;
  Eigen::Vector2d p;
  EXPECT_TRUE(ProjectPoint(unit, Eigen::Vector3d(std::sin(theta), 0, std::cos(theta)), &p));
  return p.x();
}

// `shape` with the focal length that puts the half field of view at kCircleRadiusPx, a slightly
// anisotropic focal length and an off-centre principal point.
CameraIntrinsics Lens(CameraIntrinsics shape, double fov_deg) {
  const double f = kCircleRadiusPx / NormalisedRadius(shape, fov_deg / 2 * M_PI / 180);
  shape.fku_px = f, shape.fkv_px = 1.003 * f;
  shape.u0_px = 515.3, shape.v0_px = 508.6;
  return shape;
}

std::vector<CameraIntrinsics> Shapes() {
  CameraIntrinsics unified, eucm, ds, equi;
  unified.family = LensFamily::kUnified;
  unified.xi = 0.9, unified.k1 = -0.05, unified.k2 = 0.01, unified.p1 = 2e-4, unified.p2 = -1e-4;
  eucm.family = LensFamily::kEucm;
  eucm.alpha = 0.6, eucm.beta = 1.1;
  ds.family = LensFamily::kDoubleSphere;
  ds.xi = -0.2, ds.alpha = 0.6;  // As real fisheyes fit (TUM VI: xi -0.19, alpha 0.59).
  equi.family = LensFamily::kEquidistant;
  equi.k1 = -0.01, equi.k2 = 0.002, equi.k3 = -5e-4, equi.k4 = 1e-4;
  return {unified, eucm, ds, equi};
}

SyntheticBoardViews WideViews(const CameraIntrinsics& truth, double fov_deg, uint64_t seed,
                              int views = 20) {
  Rng rng(seed);
  WideBoardOptions o;
  o.num_views = views;
  o.max_angle_deg = fov_deg / 2;
  o.pixel_sigma_px = kNoisePx;
  o.image_width = o.image_height = kImageSide;
  return MakeWideBoardViews(truth, o, &rng);
}

struct Fit {
  WideInitResult start;
  RefineResult refined;
};

Fit Calibrate(const std::vector<View>& views, LensModel model) {
  Fit fit;
  WideInitOptions o;
  o.model = model;
  o.image_width = o.image_height = kImageSide;
  fit.start = InitializeWideCamera(views, o);
  if (!fit.start.IsUsable()) return fit;
  std::vector<View> used;
  for (int v : fit.start.used_views) used.push_back(views[v]);
  RefineOptions r;
  r.model = model;
  r.estimate_skew = false;
  fit.refined = RefineCalibration(used, fit.start.intrinsics, fit.start.cam_from_board, r);
  return fit;
}

// The parameters' z-scores (estimate - truth) / reported std, 58 checks: 9 (unified: f, c, xi,
// k1, k2, p1, p2) + 6 (eucm) + 6 (double sphere) + 8 (equidistant: f, c, k1..k4) per lens, at
// 160 and 190 degrees. With correct standard deviations each |z| exceeds 2 with probability
// 4.55 %: 2.6 of 58 are expected outside 2 std by chance, and 7 or more with probability 1.8 %.
// So: at most kAllowedBeyondTwoStd of them beyond 2 std, none beyond kMaxAbsZ (3.5 std: 2.7 % for
// one of 58 by chance). Fixed seeds; measured (printed): 3 of 58 beyond 2 std (equidistant 160
// deg fku +2.95, fkv +2.74: one fact, the two focal lengths move together; the double sphere 190
// deg u0 -2.37), the largest |z| 2.95, the median |z| 0.72, the mean z^2 0.95.
// Mutations caught: BoardPoseFromRays without the turn onto the mean ray (the double sphere at
// 190 deg lands 52 std off); the double sphere's start from the xi = +0.2 branch alone (85-144
// std off at the same RMS: the fold of DoubleSphereStart).
constexpr int kAllowedBeyondTwoStd = 6;
constexpr double kMaxAbsZ = 3.5;
// The refined RMS is the noise's: sqrt(2) kNoisePx per point less the parameters' share; 10 %.
constexpr double kRmsTol = 0.1;

TEST(WideInit, EveryWideFamilyAt160And190DegreesLandsWithinItsStd) {
  int checks = 0, beyond_two = 0;
  double worst = 0;
  uint64_t seed = 100;
  for (double fov : {160.0, 190.0}) {
    for (const CameraIntrinsics& shape : Shapes()) {
      const CameraIntrinsics truth = Lens(shape, fov);
      const SyntheticBoardViews data = WideViews(truth, fov, ++seed);
      ASSERT_EQ(data.views.size(), 20u);
      const Fit fit = Calibrate(data.views, FullModelOf(truth.family));
      const std::string what = std::string(ToString(truth.family)) + " " + std::to_string(fov);
      ASSERT_TRUE(fit.start.IsUsable()) << what << ": " << fit.start.message;
      ASSERT_TRUE(fit.refined.IsUsable()) << what << ": " << fit.refined.message;
      std::printf("[ measured ] %s deg: %s\n", what.c_str(), fit.start.message.c_str());
      EXPECT_NEAR(fit.refined.rms_reproj_px, std::sqrt(2.0) * kNoisePx, kRmsTol * kNoisePx * 1.5)
          << what;
      const auto est = fit.refined.intrinsics.Params(), want = truth.Params();
      std::printf("[ measured ] %s deg z:", what.c_str());
      for (int i = 0; i < 10; ++i) {
        const double sigma = fit.refined.intrinsics_std[i];
        if (!std::isfinite(sigma)) continue;
        const double z = (est[i] - want[i]) / sigma;
        std::printf(" %s %+.2f", ParamNames(truth.family)[i], z);
        ++checks;
        beyond_two += std::abs(z) > 2;
        worst = std::max(worst, std::abs(z));
        EXPECT_LT(std::abs(z), kMaxAbsZ) << what << " " << ParamNames(truth.family)[i];
      }
      std::printf("\n");
    }
  }
  std::printf("[ measured ] %d checks, %d beyond 2 std, largest |z| %.2f\n", checks, beyond_two,
              worst);
  EXPECT_EQ(checks, 58);
  EXPECT_LE(beyond_two, kAllowedBeyondTwoStd);
}

// The wide start's reach: fields of view from 120 to 220 degrees (equidistant to 180: its
// projection stops at 90 deg) with partial boards (30 % of a board's corners suffice) and boards
// at the image circle's edge, 12 views each. The start must succeed, pose every view and the
// refinement reach the noise (2 kRmsTol). Measured (printed): start RMS 0.27-1.7 px, refined
// 0.269-0.287 px. Beyond this test (5 seeds each, the same lenses): 240 deg 15 of 15, 260 deg 9
// of 10 (eucm stuck at 3.7 px once; the double sphere here stops at 246 deg), partial boards of
// 8 of 48 corners, 4 views, the principal point 80 px off centre: all; 60 deg: unified's xi is
// not observable (19 of 20).
// Mutation caught: BoardPoseFromRays without the turn onto the mean ray (Q = I): the views past
// 90 degrees are not posed (and at 190 degrees the double sphere lands 50 std off).
TEST(WideInit, StartsFrom120To220DegreesWithPartialBoards) {
  uint64_t seed = 500;
  for (double fov : {120.0, 150.0, 180.0, 200.0, 220.0}) {
    for (const CameraIntrinsics& shape : Shapes()) {
      if (shape.family == LensFamily::kEquidistant && fov > 180) continue;
      const CameraIntrinsics truth = Lens(shape, fov);
      Rng rng(++seed);
      WideBoardOptions o;
      o.num_views = 12;
      o.max_angle_deg = fov / 2;
      o.min_visible_fraction = 0.3;
      o.pixel_sigma_px = kNoisePx;
      o.image_width = o.image_height = kImageSide;
      const SyntheticBoardViews data = MakeWideBoardViews(truth, o, &rng);
      size_t partial = 0;
      for (const View& v : data.views) partial += v.points.size() < 48;
      const Fit fit = Calibrate(data.views, FullModelOf(truth.family));
      const std::string what = std::string(ToString(truth.family)) + " " + std::to_string(fov);
      ASSERT_TRUE(fit.start.IsUsable()) << what << ": " << fit.start.message;
      ASSERT_TRUE(fit.refined.IsUsable()) << what << ": " << fit.refined.message;
      std::printf("[ measured ] %s deg, %zu partial boards: start RMS %.3g px, refined %.4g px\n",
                  what.c_str(), partial, fit.start.rms_reproj_px, fit.refined.rms_reproj_px);
      EXPECT_NEAR(fit.refined.rms_reproj_px, std::sqrt(2.0) * kNoisePx, 2 * kRmsTol * kNoisePx)
          << what;
      // Every view posed, those past 90 degrees too (equidistant leaves them out by design).
      if (truth.family != LensFamily::kEquidistant) {
        EXPECT_EQ(fit.start.used_views.size(), data.views.size()) << what;
      }
    }
  }
}

// The failure paths: each refusal says why, and a start that finds no lens gives the best RMS it
// reached (the "when it fails, the error says so, with the best RMS it found").
TEST(WideInit, FailuresSayWhyWithTheBestRmsFound) {
  const CameraIntrinsics truth = Lens(Shapes()[0], 190);
  const SyntheticBoardViews good = WideViews(truth, 190, 41, 8);
  WideInitOptions o;
  o.model = LensModel::kDoubleSphere;
  o.image_width = o.image_height = kImageSide;

  const WideInitResult one = InitializeWideCamera({good.views[0]}, o);
  EXPECT_FALSE(one.IsUsable());
  EXPECT_NE(one.message.find("at least 2 views"), std::string::npos) << one.message;

  std::vector<View> bent = good.views;
  bent[3].points[5].z() = 0.01;
  const WideInitResult not_planar = InitializeWideCamera(bent, o);
  EXPECT_FALSE(not_planar.IsUsable());
  EXPECT_NE(not_planar.message.find("view 3 is not planar"), std::string::npos)
      << not_planar.message;

  // Pixels that belong to no board through any lens: uniform over the image.
  std::vector<View> noise = good.views;
  Rng rng(5);
  for (View& v : noise) {
    for (Eigen::Vector2d& pixel : v.pixels) {
      const double v_px = rng.Uniform(0, kImageSide);  // Last first (util/random.h).
      pixel = Eigen::Vector2d(rng.Uniform(0, kImageSide), v_px);
    }
  }
  const WideInitResult none = InitializeWideCamera(noise, o);
  EXPECT_FALSE(none.IsUsable());
  EXPECT_NE(none.message.find("RMS"), std::string::npos) << none.message;
  // The best RMS it found is that of the scan, far above any fit (a right start: < 1 px).
  EXPECT_GT(none.scan_rms_px, 10.0) << none.message;
  std::printf("[ measured ] no lens: %s\n", none.message.c_str());
}

}  // namespace
}  // namespace calibench
