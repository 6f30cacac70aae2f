// The corner-error study (detect/corner_bias.h) against its own ground truth: the renderer's black
// area is the exact projected area; a fronto-parallel 32 px tag at the default sweeps' blur has no
// systematic corner bias beyond the study's resolution; a wide blur pushes the refined edges
// outward (the white data cells inside the one-cell black ring leak into the edge profile's dark
// plateau), which the study must resolve.
#include "detect/corner_bias.h"

#include <gtest/gtest.h>

#include <cmath>

namespace calibench {
namespace {

// Systematic bias resolution: the view-to-view bias spread (~0.04 px) over sqrt(views) views, 3x.
double Resolution(const CornerStats& s, int views) { return 3 * s.view_rms_px / std::sqrt(views); }

TEST(CornerBias, FrontoParallelTagIsUnbiasedAndTheRendererExact) {
  CornerBiasOptions options;
  options.views = 16;
  options.draws = 2;
  const CornerBiasResult r = MeasureCornerBias(CornerBiasCase(), 0, options);
  ASSERT_TRUE(r.ok) << r.message;
  const CornerStageResult& edge = r.stage(CornerStage::kEdgeFit);
  EXPECT_EQ(edge.detections, options.views * options.draws);
  // 32 px tag, 24 black cells of 4 x 4 px: 768 px^2; supersampling resolves edges to 1/16 px.
  EXPECT_NEAR(r.black_area_px2, 768.0, 1e-9);
  EXPECT_NEAR(r.rendered_black_area_px2 / r.black_area_px2, 1.0, 1e-3);
  for (const CornerStats& s : edge.corners) {
    EXPECT_LT(std::abs(s.radial_px), std::max(0.01, Resolution(s, options.views)));
    EXPECT_LT(s.noise_rms_px, 0.05);  // 2 gray levels of noise: ~0.015 px (README).
  }
}

TEST(CornerBias, WideBlurPushesTheEdgesOutward) {
  CornerBiasOptions options;
  options.views = 16;
  options.draws = 2;
  CornerBiasCase c;
  c.blur_sigma_px = 1.5;
  const CornerBiasResult r = MeasureCornerBias(c, 1, options);
  ASSERT_TRUE(r.ok) << r.message;
  double radial = 0;
  for (const CornerStats& s : r.stage(CornerStage::kEdgeFit).corners) radial += s.radial_px / 4;
  EXPECT_GT(radial, 0.05);  // Measured 0.14 px (README); 0.01 px at 0.5 px of blur.
}

TEST(CornerBias, BadOptionsAreRefused) {
  CornerBiasOptions options;
  options.views = 0;
  const CornerBiasResult r = MeasureCornerBias(CornerBiasCase(), 0, options);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("views must be >= 1"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace calibench
