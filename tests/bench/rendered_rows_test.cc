// The rendered rows of runs.csv against the detector's own floor: a trial on the default sweeps'
// rig (tests/bench/rendered/short.yaml) reports the corners' RMS (corner_rms_px, Euclidean) and
// the RMS of their Cramer-Rao std per axis (corner_crlb_px); the oracle rows report neither.
#include <gtest/gtest.h>

#include <cmath>

#include "bench/config/config_io.h"
#include "bench/run/runner.h"

namespace calibench {
namespace {

// The floor of the rig's 30-45 px tags at 2 gray levels of noise: a few thousandths of a pixel
// (README: 0.0095 px per axis on the rendered rig); the bounds only reject a missing or unscaled
// value.
constexpr double kMinCrlbPx = 0.002, kMaxCrlbPx = 0.05;
// A corner cannot beat its floor: the per-axis RMS is at least kMinOverFloor of it (0.8: the
// floor is itself estimated from the residuals); and the photometric fit stays near it on the
// rig (measured 1.5x: 0.0138 against 0.0092 px), below kMaxOverFloor.
constexpr double kMinOverFloor = 0.8, kMaxOverFloor = 4.0;

TEST(RenderedRows, CornerRmsAndItsCramerRaoFloor) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(std::string(CALIBENCH_SOURCE_DIR) + "/tests/bench/rendered/short.yaml",
                            &config, &why))
      << why;
  ASSERT_EQ(config.scenarios.size(), 1u);
  ScenarioConfig rendered = config.scenarios[0];
  for (MethodInstance& m : rendered.methods) m.enabled = m.name == "ceres";
  const std::vector<RunRow> rows = RunTrial(rendered, 0);
  ASSERT_EQ(rows.size(), 1u);
  const RunRow& r = rows[0];
  ASSERT_EQ(r.status, "ok") << r.message;
  std::printf("corner RMS %.4f px (per axis %.4f), CRLB per axis %.4f px\n", r.corner_rms_px,
              r.corner_rms_px / std::sqrt(2.0), r.corner_crlb_px);
  EXPECT_GT(r.corner_crlb_px, kMinCrlbPx);
  EXPECT_LT(r.corner_crlb_px, kMaxCrlbPx);
  const double per_axis = r.corner_rms_px / std::sqrt(2.0);
  EXPECT_GT(per_axis, kMinOverFloor * r.corner_crlb_px);
  EXPECT_LT(per_axis, kMaxOverFloor * r.corner_crlb_px);

  ScenarioConfig oracle = rendered;
  oracle.detections = Detections::kOracle;
  oracle.measurements.noise.pixel_sigma_px = 0.1;
  const std::vector<RunRow> oracle_rows = RunTrial(oracle, 0);
  ASSERT_EQ(oracle_rows.size(), 1u);
  EXPECT_TRUE(std::isnan(oracle_rows[0].corner_crlb_px));
}

}  // namespace
}  // namespace calibench
