// The photometric tag fit (detect/photometric_fit.h) against independent computations: its edge
// profile against a numerical integral of the pixel box and the Gaussian PSF, its pattern against
// the family's bitmap, and its corners on rendered tags against the exact projections, with the
// Monte Carlo spread of the fit against the Cramer-Rao std it reports. Bad regions are refused
// with a reason.
//
// Mutations checked by hand: flipping the sign of a rectangle's far-edge Jacobian in Evaluate
// (weight[r[1]] -= ... -> +=) fails RenderedTagsAreUnbiasedAtTheCramerRaoBound (radial -0.048 px,
// noise 4x the bound) and FitsASharpTagDrawnCellByCell; doubling the pixel box's width in
// EdgeProfile ((a + b) / 2 -> (a + b)) fails EdgeProfileIsTheBoxAndGaussianIntegral and
// RenderedTagsAreUnbiasedAtTheCramerRaoBound.
#include "detect/photometric_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "camera/camera.h"
#include "detect/corner_bias.h"
#include "sim/render.h"
#include "sim/tag_family.h"
#include "sim/target.h"
#include "util/random.h"

namespace calibench {
namespace {

double Phi(double u) { return 0.5 * std::erfc(-u / std::sqrt(2.0)); }

// Midpoint rule on a 400 x 400 grid over the pixel box: error O(1/400^2) on a smooth integrand.
constexpr double kQuadratureTol = 2e-6;
// Central differences with h = 1e-5 of a function whose third derivative is O(1/sigma^3).
constexpr double kDerivativeTol = 1e-5;

TEST(PhotometricFit, EdgeProfileIsTheBoxAndGaussianIntegral) {
  for (double sigma : {0.3, 0.7, 1.5}) {
    for (double angle_deg : {0.0, 20.0, 45.0, 70.0}) {
      const double nx = std::cos(angle_deg * M_PI / 180), ny = std::sin(angle_deg * M_PI / 180);
      for (double d : {-1.7, -0.6, -0.2, 0.0, 0.15, 0.5, 1.2, 2.5}) {
        constexpr int kN = 400;
        double sum = 0;
        for (int i = 0; i < kN; ++i) {
          for (int j = 0; j < kN; ++j) {
            const double u = (i + 0.5) / kN - 0.5, v = (j + 0.5) / kN - 0.5;
            sum += Phi((d + nx * u + ny * v) / sigma);
          }
        }
        const EdgeProfileValue p = EdgeProfile(d, sigma, nx, ny);
        EXPECT_NEAR(p.p, sum / (kN * kN), kQuadratureTol)
            << "sigma " << sigma << " angle " << angle_deg << " d " << d;
        // Symmetric kernel: P(-d) = 1 - P(d).
        EXPECT_NEAR(EdgeProfile(-d, sigma, nx, ny).p, 1 - p.p, 1e-12);
        constexpr double h = 1e-5;
        EXPECT_NEAR(
            p.dp_dd,
            (EdgeProfile(d + h, sigma, nx, ny).p - EdgeProfile(d - h, sigma, nx, ny).p) / (2 * h),
            kDerivativeTol);
        EXPECT_NEAR(
            p.dp_dsigma,
            (EdgeProfile(d, sigma + h, nx, ny).p - EdgeProfile(d, sigma - h, nx, ny).p) / (2 * h),
            kDerivativeTol);
      }
    }
  }
}

// The quadrant correction against the bivariate normal CDF integrated directly: the density of
// (X, Y), unit variances and correlation rho, summed by the midpoint rule on [-8, a] x [-8, b] with
// 1200 x 1200 cells (error ~1e-6 of the probability), minus Phi(a) Phi(b); and its derivatives
// against central differences. Mutation checked: + 2 a b sin t in the integrand fails it.
TEST(PhotometricFit, QuadrantCorrectionIsTheBivariateNormalCdf) {
  constexpr double kCdfTol = 5e-6;
  for (double rho : {-0.6, -0.2, 0.1, 0.45, 0.8}) {
    for (const auto& [a, b] : std::vector<std::pair<double, double>>{
             {0.0, 0.0}, {0.7, -0.4}, {-1.3, 0.9}, {2.0, 1.5}, {-2.5, -0.5}}) {
      constexpr int kN = 1200;
      const double hx = (a + 8) / kN, hy = (b + 8) / kN;
      const double norm = 1 / (2 * M_PI * std::sqrt(1 - rho * rho));
      double sum = 0;
      for (int i = 0; i < kN; ++i) {
        const double x = -8 + (i + 0.5) * hx;
        for (int j = 0; j < kN; ++j) {
          const double y = -8 + (j + 0.5) * hy;
          sum += std::exp(-(x * x - 2 * rho * x * y + y * y) / (2 * (1 - rho * rho)));
        }
      }
      const double direct = norm * sum * hx * hy - Phi(a) * Phi(b);
      const QuadrantCorrection c = QuadrantCorrectionAt(a, b, rho);
      EXPECT_NEAR(c.c, direct, kCdfTol) << "rho " << rho << " a " << a << " b " << b;
      constexpr double h = 1e-5;
      EXPECT_NEAR(
          c.dc_da,
          (QuadrantCorrectionAt(a + h, b, rho).c - QuadrantCorrectionAt(a - h, b, rho).c) / (2 * h),
          kDerivativeTol);
      EXPECT_NEAR(
          c.dc_db,
          (QuadrantCorrectionAt(a, b + h, rho).c - QuadrantCorrectionAt(a, b - h, rho).c) / (2 * h),
          kDerivativeTol);
    }
  }
}

// The quadrature's node count adapts to rho (tag_model.h): against Plackett's integral by Simpson's
// rule on 2000 intervals (error < 1e-12 here), within the 5e-8 the rule promises for |a|, |b| <= 5,
// on both sides of every switch (|rho| 0.2, 0.5, 0.7, 0.9) and at and past the clamp (0.99).
// Its gradient (the quadrature's own) against the closed form phi(a) [Phi((b - rho a) /
// sqrt(1 - rho^2)) - Phi(b)] and its mirror in b: kGradientTol 2e-7, twice the largest error of the
// same rule on a 0.25 grid computed independently (scipy: 1.0e-7, at rho 0.2 with 2 nodes).
TEST(PhotometricFit, QuadrantRuleKeepsItsErrorBoundAtEveryNodeCount) {
  constexpr double kRuleTol = 5e-8, kGradientTol = 2e-7;
  auto density = [](double u) { return std::exp(-0.5 * u * u) / std::sqrt(2 * M_PI); };
  for (double rho : {0.01, -0.19, 0.2, 0.21, 0.49, -0.51, 0.69, 0.71, -0.9, 0.91, -0.99, 0.999}) {
    const QuadrantRule rule = QuadrantRuleFor(rho);
    const double r = std::clamp(rho, -0.99, 0.99), end = std::asin(r);
    const double root = std::sqrt(1 - r * r);
    for (double a = -5; a <= 5; a += 0.5) {
      for (double b = -5; b <= 5; b += 0.5) {
        const QuadrantCorrection corr = QuadrantCorrectionAt(a, b, rule);
        EXPECT_NEAR(corr.dc_da, density(a) * (Phi((b - r * a) / root) - Phi(b)), kGradientTol)
            << "rho " << rho << " a " << a << " b " << b;
        EXPECT_NEAR(corr.dc_db, density(b) * (Phi((a - r * b) / root) - Phi(a)), kGradientTol)
            << "rho " << rho << " a " << a << " b " << b;
        constexpr int kIntervals = 2000;
        const double h = end / kIntervals;
        double sum = 0;
        for (int i = 0; i <= kIntervals; ++i) {
          const double t = i * h, c = std::cos(t);
          const double f = std::exp(-(a * a + b * b - 2 * a * b * std::sin(t)) / (2 * c * c));
          sum += (i == 0 || i == kIntervals ? 1 : (i % 2 ? 4 : 2)) * f;
        }
        const double simpson = sum * h / 3 / (2 * M_PI);
        EXPECT_NEAR(QuadrantCorrectionAt(a, b, rule).c, simpson, kRuleTol)
            << "rho " << rho << " nodes " << rule.num_nodes << " a " << a << " b " << b;
      }
    }
  }
}

TEST(PhotometricFit, PatternRectanglesTileTheBitmapsBlackCells) {
  std::string why;
  for (int border : {1, 2}) {
    const auto family = TagFamily::Create("tag36h11", border, &why);
    ASSERT_TRUE(family) << why;
    const int w = family->width_at_border(), start = family->border_start();
    for (int id : {0, 7, 586}) {
      TagPattern pattern;
      ASSERT_TRUE(TagPattern::FromFamily(*family, id, 2.4, 0.0, &pattern, &why)) << why;
      // Every black cell centre in exactly one rectangle, every white one in none.
      for (int row = 0; row < w; ++row) {
        for (int col = 0; col < w; ++col) {
          const double x = col + 0.5, y = w - row - 0.5;
          int covered = 0;
          for (const TagPattern::Rect& r : pattern.black)
            covered += x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1;
          EXPECT_EQ(covered, family->IsWhite(id, start + col, start + row) ? 0 : 1)
              << "border " << border << " id " << id << " cell " << col << "," << row;
        }
      }
    }
  }
  const auto family = TagFamily::Create("tag36h11", 1, &why);
  TagPattern pattern;
  EXPECT_FALSE(TagPattern::FromFamily(*family, 587, 2.4, 0.0, &pattern, &why));
  EXPECT_NE(why.find("not in tag36h11"), std::string::npos) << why;
}

// Rendered single tags (detect/corner_bias.h: exact cell areas a pixel), blur 1 px: the renderer's
// sampled Gaussian kernel is close to the continuous PSF the model assumes from sigma ~ 1 px (at
// 0.5 px its three taps leave 3-4 gray levels of misfit, README). Bias bound: 0.005 px, the
// issue's target for the physical floor (12 views: the bias's standard error is ~0.001 px).
// Spread: the per-axis noise of the corners over draws against the fit's own Cramer-Rao std,
// within [0.5, 1.5] (measured 0.7-0.8: the bound uses the residual variance, which holds the
// renderer's quantisation as well as the noise).
constexpr double kBiasTolPx = 0.005;
constexpr double kMinSpreadOverCrlb = 0.5, kMaxSpreadOverCrlb = 1.5;

TEST(PhotometricFit, RenderedTagsAreUnbiasedAtTheCramerRaoBound) {
  CornerBiasOptions options;
  options.views = 12;
  options.draws = 3;
  options.supersample = 16;
  struct Case {
    double tag_px, tilt_deg, roll_deg;
  };
  for (const Case& k : {Case{48, 0, 0}, Case{32, 30, 10}, Case{64, 20, 22.5}}) {
    CornerBiasCase c;
    c.tag_px = k.tag_px;
    c.tilt_deg = k.tilt_deg;
    c.roll_deg = k.roll_deg;
    c.blur_sigma_px = 1.0;
    const CornerBiasResult r = MeasureCornerBias(c, 3, options);
    ASSERT_TRUE(r.ok) << r.message;
    const CornerStageResult& photometric = r.stage(CornerStage::kPhotometric);
    EXPECT_EQ(photometric.detections, options.views * options.draws) << k.tag_px;
    double radial = 0, noise = 0, edge_noise = 0;
    for (int i = 0; i < 4; ++i) {
      radial += photometric.corners[i].radial_px / 4;
      noise += photometric.corners[i].noise_rms_px / 4;
      edge_noise += r.stage(CornerStage::kEdgeFit).corners[i].noise_rms_px / 4;
    }
    const double per_axis = noise / std::sqrt(2.0);
    std::printf(
        "tag %g px, tilt %g: radial %+.4f px, noise per axis %.4f px, CRLB %.4f px, "
        "edge fit noise per axis %.4f px\n",
        k.tag_px, k.tilt_deg, radial, per_axis, r.crlb_px, edge_noise / std::sqrt(2.0));
    EXPECT_LT(std::abs(radial), kBiasTolPx) << k.tag_px;
    EXPECT_GT(per_axis, kMinSpreadOverCrlb * r.crlb_px) << k.tag_px;
    EXPECT_LT(per_axis, kMaxSpreadOverCrlb * r.crlb_px) << k.tag_px;
    EXPECT_LT(noise, edge_noise);  // The whole pattern beats four edge windows.
  }
}

// A 640 x 480 pinhole camera (f 800 px) and a grid of one 10 cm tag (with Kalibr's corner squares
// or without): 2 m away the tag is 40 px wide.
const CameraIntrinsics kOneTagCamera{800.0, 800.0, 90.0, 319.5, 239.5};
AprilGrid OneTagGrid(bool corner_squares) {
  AprilGrid grid;
  grid.tag_rows = grid.tag_cols = 1;
  grid.tag_size_m = 0.1;
  grid.corner_squares = corner_squares;
  return grid;
}

// The exact corners of a one-tag grid seen from `cam_from_board`, and a start 0.3 px off each in
// x and y (outwards or inwards), as a detector's corners would be.
testing::AssertionResult CornersAndStart(const CameraIntrinsics& camera, const AprilGrid& grid,
                                         const Rigid3& cam_from_board,
                                         std::array<Eigen::Vector2d, 4>* truth,
                                         std::array<Eigen::Vector2d, 4>* start) {
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  for (int k = 0; k < 4; ++k) {
    if (!ProjectPoint(camera, cam_from_board * corners[k], &(*truth)[k])) {
      return testing::AssertionFailure() << "corner " << k << " does not project";
    }
    (*start)[k] = (*truth)[k] + Eigen::Vector2d(k % 2 ? 0.3 : -0.3, k < 2 ? 0.3 : -0.3);
  }
  return testing::AssertionSuccess();
}

// The PSF is a fitted parameter: on a tag the renderer blurs by sigma = 1 px (16 x 16 samples, 2
// gray levels of noise), fitted from corners 0.3 px off, sigma comes back within kBlurTolPx (the
// renderer's sampled kernel against the continuous Gaussian of the model: measured < 0.02 px) and
// the corners within kCornerTolPx of the exact projections (~3 CRLB of a 40 px tag).
constexpr double kBlurTolPx = 0.05, kCornerTolPx = 0.02;

TEST(PhotometricFit, FitsTheRenderersBlur) {
  std::string why;
  const CameraIntrinsics camera = kOneTagCamera;
  const AprilGrid grid = OneTagGrid(false);
  const auto family = TagFamily::Create(grid.family, grid.black_tag_border, &why);
  ASSERT_TRUE(family) << why;
  BoardView view{grid, family, {}};
  // Board y up in the image, facing the camera, its tag 40 px wide, slightly rotated and tilted.
  view.cam_from_board.rotation = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))
                                     .toRotationMatrix();
  view.cam_from_board.translation =
      Eigen::Vector3d(0, 0, 2.0) - view.cam_from_board.rotation * Eigen::Vector3d(0.05, 0.05, 0);
  RenderOptions render;
  render.supersample = 16;
  render.blur_sigma_px = 1.0;
  render.noise_sigma_gray = 2.0;
  const auto renderer = FrameRenderer::Create(camera, render, &why);
  ASSERT_TRUE(renderer) << why;
  GrayImage image;
  Rng rng(7);
  ASSERT_TRUE(renderer->Render({view}, &rng, &image, &why)) << why;
  std::array<Eigen::Vector2d, 4> truth, start;
  ASSERT_TRUE(CornersAndStart(camera, grid, view.cam_from_board, &truth, &start));
  TagPattern pattern;
  ASSERT_TRUE(TagPattern::FromFamily(*family, 0, grid.tag_spacing * family->width_at_border(), 0.0,
                                     &pattern, &why))
      << why;
  const PhotometricFitResult fit = FitTagPhotometric(image, pattern, start, {});
  ASSERT_TRUE(fit.ok()) << fit.message;
  std::printf("fitted blur %.4f px (rendered 1), corner errors", fit.blur_px);
  EXPECT_NEAR(fit.blur_px, render.blur_sigma_px, kBlurTolPx);
  for (int k = 0; k < 4; ++k) {
    std::printf(" %.4f", (fit.corners[k] - truth[k]).norm());
    EXPECT_LT((fit.corners[k] - truth[k]).norm(), kCornerTolPx) << "corner " << k;
  }
  std::printf(" px\n");
}

// Another board in front of a grid's tag covers the white margin and the corner squares on one
// side of it (two boards next to each other in a 190 deg scenario did this; a finger holding a
// board does it too). The plain least-squares fit explains those pixels by moving the tag: its
// corners move by more than kCoveredPulledPx (measured 0.15-0.64 px, the covered side's most).
// The robust pass leaves them out with their blurred rim and fits the rest. Over kCoveredDraws
// noise draws each corner's mean error stays within kBiasTolPx (measured <= 0.003 px), its
// spread per axis within kMaxSpreadOverCrlb of the CRLB the fit reports, which on the covered
// side is larger than the uncovered tag's (fewer pixels remain); on the tag alone nothing is left
// out.
constexpr double kCoveredPulledPx = 0.05;
constexpr int kCoveredDraws = 8;

TEST(PhotometricFit, PixelsCoveredByAnotherBoardAreLeftOut) {
  std::string why;
  const CameraIntrinsics camera = kOneTagCamera;
  const AprilGrid grid = OneTagGrid(true);
  const auto family = TagFamily::Create(grid.family, grid.black_tag_border, &why);
  ASSERT_TRUE(family) << why;
  const Eigen::Matrix3d facing = (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))
                                     .toRotationMatrix();
  BoardView tag{grid, family, {}};
  tag.cam_from_board.rotation = facing;
  tag.cam_from_board.translation =
      Eigen::Vector3d(0, 0, 2.0) - facing * Eigen::Vector3d(0.05, 0.05, 0);
  // The cover: the same board 0.2 m nearer and shifted along its x, so that its left edge (the
  // white board reaches 2 g = 6 cm past the tag) lies 0.8 cm clear of the tag's black square, in
  // the tag's frame: its white margin over the tag's right-hand margin and corner squares, its
  // own corner squares just beyond the tag's region. (x_cover - 0.11) / 1.8 = 0.058 / 2.0.
  BoardView cover = tag;
  cover.cam_from_board.translation =
      Eigen::Vector3d(0, 0, 1.8) + facing * Eigen::Vector3d(0.1622 - 0.05, -0.05, 0);
  RenderOptions render;
  render.supersample = 8;
  render.blur_sigma_px = 1.0;
  render.noise_sigma_gray = 2.0;
  const auto renderer = FrameRenderer::Create(camera, render, &why);
  ASSERT_TRUE(renderer) << why;
  std::array<Eigen::Vector2d, 4> truth, start;
  ASSERT_TRUE(CornersAndStart(camera, grid, tag.cam_from_board, &truth, &start));
  TagPattern pattern;
  ASSERT_TRUE(TagPattern::FromFamily(*family, 0, grid.tag_spacing * family->width_at_border(),
                                     grid.tag_spacing * family->width_at_border(), &pattern, &why))
      << why;
  PhotometricFitOptions least_squares;
  least_squares.max_outlier_rounds = 0;
  std::array<Eigen::Vector2d, 4> bias_robust, bias_pulled;
  std::array<double, 4> sq_robust{}, crlb_robust{}, crlb_clean{};
  bias_robust.fill(Eigen::Vector2d::Zero());
  bias_pulled.fill(Eigen::Vector2d::Zero());
  int left_out = 0;
  for (int draw = 0; draw < kCoveredDraws; ++draw) {
    GrayImage alone, covered;
    Rng rng(100 + draw), same_noise(100 + draw);
    ASSERT_TRUE(renderer->Render({tag}, &rng, &alone, &why)) << why;
    ASSERT_TRUE(renderer->Render({tag, cover}, &same_noise, &covered, &why)) << why;
    const PhotometricFitResult clean = FitTagPhotometric(alone, pattern, start, {});
    const PhotometricFitResult pulled = FitTagPhotometric(covered, pattern, start, least_squares);
    const PhotometricFitResult robust = FitTagPhotometric(covered, pattern, start, {});
    ASSERT_TRUE(clean.ok() && pulled.ok() && robust.ok())
        << clean.message << pulled.message << robust.message;
    EXPECT_EQ(clean.outlier_pixels, 0);  // Nothing disagrees on a tag alone.
    left_out += robust.outlier_pixels;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d e = robust.corners[k] - truth[k];
      bias_robust[k] += e / kCoveredDraws;
      bias_pulled[k] += (pulled.corners[k] - truth[k]) / kCoveredDraws;
      sq_robust[k] += e.squaredNorm() / (2 * kCoveredDraws);
      crlb_robust[k] += robust.crlb_px[k] / kCoveredDraws;
      crlb_clean[k] += clean.crlb_px[k] / kCoveredDraws;
    }
  }
  double worst_pulled = 0;
  std::printf(
      "covered: %d px a draw left out; per corner mean error least squares / robust, "
      "robust spread per axis, CRLB covered / alone:\n",
      left_out / kCoveredDraws);
  for (int k = 0; k < 4; ++k) {
    const double spread = std::sqrt(std::max(0.0, sq_robust[k] - bias_robust[k].squaredNorm() / 2));
    std::printf("  corner %d: %.4f / %.4f px, %.4f px, %.4f / %.4f px\n", k, bias_pulled[k].norm(),
                bias_robust[k].norm(), spread, crlb_robust[k], crlb_clean[k]);
    worst_pulled = std::max(worst_pulled, bias_pulled[k].norm());
    EXPECT_LT(bias_robust[k].norm(), kBiasTolPx) << "corner " << k;
    EXPECT_LT(spread, kMaxSpreadOverCrlb * crlb_robust[k]) << "corner " << k;
    // The covered side's corners lose the most pixels (measured +30% / +26%; the others < 1%).
    if (k == 1 || k == 2) {
      EXPECT_GT(crlb_robust[k], crlb_clean[k]) << "corner " << k;
    }
  }
  EXPECT_GT(left_out, 0);
  EXPECT_GT(worst_pulled, kCoveredPulledPx);  // Without the robust pass the test would fail.
}

// An EuRoC-like lens (k1 = -0.28, k2 = 0.074, f 458 px, 752 x 480): a 60 px tag near the image
// corner, where the lens bends its edges by ~0.3 px over the tag. Through a homography in pixels
// the fit cannot follow the bend; drawn through the camera it can (same 0.005 px bias bound).
// The corner study's options for `views` sub-pixel shifted views of `draws` noise draws each.
CornerBiasOptions StudyFrames(int views, int draws) {
  CornerBiasOptions options;
  options.views = views;
  options.draws = draws;
  return options;
}

TEST(PhotometricFit, LensAwareFitFollowsTheBentEdges) {
  CornerBiasOptions options = StudyFrames(8, 2);
  options.supersample = 16;
  CornerBiasCase c;
  c.lens = CornerBiasLens::kRadTanEuroc;
  c.tag_px = 60;
  c.tilt_deg = 20;
  c.blur_sigma_px = 1.0;
  c.centre_px = Eigen::Vector2d(130, 110);
  const CornerBiasResult r = MeasureCornerBias(c, 5, options);
  ASSERT_TRUE(r.ok) << r.message;
  const CornerStageResult& plain = r.stage(CornerStage::kPhotometric);
  const CornerStageResult& aware = r.stage(CornerStage::kLensAware);
  EXPECT_EQ(aware.detections, options.views * options.draws);
  double worst_plain = 0, worst_aware = 0, radial_aware = 0;
  for (int i = 0; i < 4; ++i) {
    worst_plain = std::max(worst_plain, plain.corners[i].bias.norm());
    worst_aware = std::max(worst_aware, aware.corners[i].bias.norm());
    radial_aware += aware.corners[i].radial_px / 4;
  }
  std::printf(
      "EuRoC-like lens, 60 px tag at (130, 110): worst corner bias %.4f px through a "
      "homography, %.4f px through the lens (radial %+.4f px); CRLB %.4f px\n",
      worst_plain, worst_aware, radial_aware, r.crlb_px);
  EXPECT_GT(worst_plain, 10 * kBiasTolPx);  // The bend is visible without the lens (0.38 px)...
  // ... and gone with it: the mean radial bias within the bound, each corner's 2D bias within
  // twice it (one corner's bias over 16 draws has a standard error of ~0.002 px in norm).
  EXPECT_LT(std::abs(radial_aware), kBiasTolPx);
  EXPECT_LT(worst_aware, 2 * kBiasTolPx);
}

// Blurring a curved edge moves its mean-level crossing towards its centre of curvature by
// kappa s^2 / 2 (s^2 = sigma^2 + 1/12): the lens-aware fit draws the lens's bend of each edge and
// must shift its straight-edge profile by as much (tag_fit.h PatternLines::bend_shift). A 32 px
// tag 95 deg off the axis of the 190 deg double-sphere lens, blur 1.5 px, 24 views x 8 draws:
// the tag's translation (the mean of its four corners' biases), which a calibration follows.
// Measured: 0.0006 px with the shift, 0.0035 px without it (the mutation). Tolerance
// kTranslationTolPx: the measured 0.0006 px plus ~2.5 standard errors of the translation (0.0005
// px per axis: 768 corners at ~0.015 px).
TEST(PhotometricFit, LensAwareFitShiftsABlurredBentEdgeToItsCrossing) {
  constexpr double kTranslationTolPx = 0.002;
  const CornerBiasOptions options = StudyFrames(24, 8);
  CornerBiasCase blurred_at_95_deg;  // The lens's default place: 95 deg off the axis.
  blurred_at_95_deg.lens = CornerBiasLens::kDoubleSphere190;
  blurred_at_95_deg.blur_sigma_px = 1.5;
  const CornerBiasResult r = MeasureCornerBias(blurred_at_95_deg, 82, options);
  ASSERT_TRUE(r.ok) << r.message;
  const CornerStageResult& aware = r.stage(CornerStage::kLensAware);
  EXPECT_EQ(aware.detections, options.views * options.draws);
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  for (int i = 0; i < 4; ++i) translation += aware.corners[i].bias / 4;
  std::printf(
      "190 deg double sphere, 32 px tag at 95 deg, blur 1.5 px: tag translation (%+.4f, "
      "%+.4f) px\n",
      translation.x(), translation.y());
  EXPECT_LT(translation.norm(), kTranslationTolPx);
}

// A rendered 40 px tag in the middle of a 160 x 160 frame, its detector corners.
struct OneTag {
  GrayImage image;
  TagPattern pattern;
  std::array<Eigen::Vector2d, 4> corners;
};
OneTag RenderOneTag() {
  OneTag t;
  std::string why;
  const auto family = TagFamily::Create("tag36h11", 1, &why);
  TagPattern::FromFamily(*family, 0, 2.4, 0.0, &t.pattern, &why);
  // The pattern drawn directly: 5 px cells, black square [40, 80]^2 (y up in tag = rows down).
  t.image.width = t.image.height = 160;
  t.image.pixels.assign(160 * 160, 230);
  for (const TagPattern::Rect& r : t.pattern.black) {
    for (int y = static_cast<int>(r.y0 * 5); y < r.y1 * 5; ++y)
      for (int x = static_cast<int>(r.x0 * 5); x < r.x1 * 5; ++x)
        t.image.pixels[(79 - y) * 160 + 40 + x] = 25;
  }
  // Corner 0 (tag (0, 0)) at the bottom-left: the black pixels span columns and rows 40..79.
  t.corners = {Eigen::Vector2d(39.5, 79.5), Eigen::Vector2d(79.5, 79.5),
               Eigen::Vector2d(79.5, 39.5), Eigen::Vector2d(39.5, 39.5)};
  return t;
}

TEST(PhotometricFit, FitsASharpTagDrawnCellByCell) {
  const OneTag t = RenderOneTag();
  std::array<Eigen::Vector2d, 4> start = t.corners;
  for (int k = 0; k < 4; ++k) start[k] += Eigen::Vector2d(0.3 * (k % 2) - 0.2, 0.25 - 0.1 * k);
  const PhotometricFitResult fit = FitTagPhotometric(t.image, t.pattern, start, {});
  ASSERT_TRUE(fit.ok()) << fit.message;
  // Pixel-aligned edges, no blur, no noise: the model is exact up to its sigma floor (0.02 px).
  for (int k = 0; k < 4; ++k) EXPECT_LT((fit.corners[k] - t.corners[k]).norm(), 1e-3) << k;
  EXPECT_NEAR(fit.black_gray, 25, 0.5);
  EXPECT_NEAR(fit.white_gray, 230, 0.5);
  EXPECT_LT(fit.blur_px, 0.05);
}

TEST(PhotometricFit, BadRegionsAreRefusedWithAReason) {
  const OneTag t = RenderOneTag();
  const PhotometricFitOptions options;
  {  // The region (black square + 2.4 cells of white) cut by the image border.
    std::array<Eigen::Vector2d, 4> corners = t.corners;
    for (Eigen::Vector2d& c : corners) c -= Eigen::Vector2d(50, 0);  // 35% of it outside.
    const PhotometricFitResult fit = FitTagPhotometric(t.image, t.pattern, corners, options);
    EXPECT_EQ(fit.failure, FitFailure::kImageBorder) << fit.message;
    EXPECT_NE(fit.message.find("image border"), std::string::npos) << fit.message;
    EXPECT_EQ(fit.corners[0], corners[0]);  // Unchanged.
  }
  for (uint8_t gray : {uint8_t{128}, uint8_t{255}}) {  // Constant, and saturated.
    GrayImage flat = t.image;
    std::fill(flat.pixels.begin(), flat.pixels.end(), gray);
    const PhotometricFitResult fit = FitTagPhotometric(flat, t.pattern, t.corners, options);
    EXPECT_EQ(fit.failure, FitFailure::kLowContrast) << fit.message;
    EXPECT_NE(fit.message.find("contrast"), std::string::npos) << fit.message;
  }
  {  // No tag there: uniform noise. Whatever the reason, the fit must not claim a tag.
    GrayImage noise = t.image;
    Rng rng(7);
    for (uint8_t& v : noise.pixels) v = static_cast<uint8_t>(rng.Uniform(0, 255));
    const PhotometricFitResult fit = FitTagPhotometric(noise, t.pattern, t.corners, options);
    EXPECT_FALSE(fit.ok()) << "residual " << fit.residual_rms_gray;
    EXPECT_FALSE(fit.message.empty());
  }
  {  // Degenerate corners.
    std::array<Eigen::Vector2d, 4> corners;
    corners.fill(Eigen::Vector2d(80, 80));
    const PhotometricFitResult fit = FitTagPhotometric(t.image, t.pattern, corners, options);
    EXPECT_EQ(fit.failure, FitFailure::kDiverged) << fit.message;
  }
  PhotometricFitOptions bad;
  bad.max_blur_px = -1;
  std::string why;
  EXPECT_FALSE(bad.Check(&why));
  EXPECT_NE(why.find("max_blur_px"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
