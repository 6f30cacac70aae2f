// Method `ceres` through the registry: exact from dlt on noise-free data; on noisy data its
// reported standard deviations match the Cramer-Rao bound of its parametrisation; an init that
// fails gives a failed result naming it; `views: init` re-solves exactly zhang's views (zhang's
// twin) and reports their data.
#include <gtest/gtest.h>

#include "methods/options.h"
#include "metrics/metrics.h"
#include "sim/synthetic.h"
#include "tests/common/method_input.h"
#include "util/random.h"

namespace calibench {
namespace {

CameraSpec TruthOf(const SceneTruth& scene) {
  return {scene.intrinsics, scene.parent_from_cam.rotation, scene.parent_from_cam.translation,
          scene.allow_improper_rotation};
}

TEST(CeresMethod, IsExactFromTheDltOnNoiseFreeData) {
  const ThesisSimulation sim = *MakeThesisSimulation(3);
  auto trial = SyntheticTrial::Create(sim.scene, sim.measurements, 1);
  ASSERT_NE(trial, nullptr);
  const MethodResult r = MakeMethod("ceres")->Run(trial->input, nullptr);
  ASSERT_TRUE(r.IsUsable()) << r.message;
  const CameraErrors e = CameraErrorsAgainst(r.estimate, TruthOf(sim.scene));
  EXPECT_LT(std::abs(e.fku_px) / 822, 1e-6);
  EXPECT_LT(std::abs(e.phi_deg) / 87, 1e-6);
  EXPECT_LT(e.position_m, 1e-6);
  EXPECT_LT(ThetaErrorOf(r.estimate, TruthOf(sim.scene)), 1e-6);
}

// 150 random points seen 50 times with 0.5 px noise (configs/batch/crlb50.yaml's scene): ceres's
// reported std (sigma estimated from the residuals) and the CRLB at the truth (sigma known) agree
// within 20% (different points of evaluation and sigma estimate; README: ratio 1.00-1.05).
TEST(CeresMethod, ReportedStdMatchesTheCramerRaoBound) {
  ThesisSimulation sim = *MakeThesisSimulation(3);
  Rng rng(50, RngStream::kScene);
  sim.scene.points.clear();
  for (int i = 0; i < 150; ++i) {
    const double z = rng.Uniform(-4, 5), y = rng.Uniform(15, 30);  // Last first: util/random.h.
    sim.scene.points.emplace_back(rng.Uniform(-6, 6), y, z);
  }
  sim.scene.duration_s = 50;
  OracleOptions options;
  options.sample_rate_hz = 1;
  options.noise.pixel_sigma_px = 0.5;
  auto trial = SyntheticTrial::Create(sim.scene, options, 7);
  ASSERT_NE(trial, nullptr);
  const std::unique_ptr<Method> method = MakeMethod("ceres");
  const MethodResult r = method->Run(trial->input, nullptr);
  ASSERT_TRUE(r.IsUsable()) << r.message;
  const CrlbStd bound = CramerRaoStd(trial->input.Frames().views, TruthOf(sim.scene),
                                     *method->BoundParametrisation(), 0.5);
  ASSERT_TRUE(bound.valid);
  EXPECT_NEAR(r.estimate.intrinsics_std[0] / bound.std_px[0], 1.0, 0.2);
  EXPECT_NEAR(r.estimate.intrinsics_std[3] / bound.std_px[3], 1.0, 0.2);
}

TEST(CeresMethod, AFailedInitIsNamed) {
  ThesisSimulation sim = *MakeThesisSimulation(3);
  sim.scene.points.resize(5);  // The DLT needs 6 distinct points.
  sim.scene.motion = Motion();
  auto trial = SyntheticTrial::Create(sim.scene, sim.measurements, 1);
  ASSERT_NE(trial, nullptr);
  const MethodResult r = MakeMethod("ceres")->Run(trial->input, nullptr);
  EXPECT_EQ(r.status, MethodStatus::kFailed);
  EXPECT_NE(r.message.find("initialisation (dlt) failed: the DLT needs at least 6 distinct points"),
            std::string::npos)
      << r.message;
  const std::unique_ptr<Method> m = MakeMethod("ceres");
  std::string why;
  EXPECT_FALSE(SetOption(m.get(), "init", "", &why));
  EXPECT_NE(why.find("init must name"), std::string::npos) << why;
}

// zhang's twin: with zhang's lens model on zhang's views (per-view poses, no rig constraint) the
// maximum-likelihood optimum is zhang's own, so the intrinsics agree to what calibrateCamera's
// float32 points and stopping rule leave (kOptimiserPx); both report the same data, fewer frames
// than the trial's; an init without per-view problems is refused by name.
TEST(CeresMethod, ViewsInitReSolvesZhangsViews) {
  constexpr double kOptimiserPx = 1e-3;
  const BoardRigScene rig = SwayingBoardRig();
  OracleOptions options;
  options.sample_rate_hz = 2;
  options.noise.pixel_sigma_px = 0.3;
  auto trial = SyntheticTrial::Create(rig.scene, options, 3, rig.layouts);
  ASSERT_NE(trial, nullptr);
  std::unique_ptr<Method> twin = MakeMethod("ceres");
  std::string why;
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, std::string>>{{"init", "zhang"},
                                                        {"views", "init"},
                                                        {"model", "pinhole-k2"},
                                                        {"estimate_skew", "false"}}) {
    ASSERT_TRUE(SetOption(twin.get(), key, value, &why)) << key << ": " << why;
  }
  EXPECT_FALSE(twin->BoundParametrisation().has_value());  // Not the rig's bound.
  const MethodResult r = twin->Run(trial->input, nullptr);
  const MethodResult& zhang = trial->input.Prerequisite("zhang");
  ASSERT_TRUE(r.IsUsable()) << r.message;
  ASSERT_TRUE(zhang.IsUsable()) << zhang.message;
  const IntrinsicsArray a = r.estimate.intrinsics.Params(), b = zhang.estimate.intrinsics.Params();
  for (int i : {0, 1, 3, 4}) EXPECT_NEAR(a[i], b[i], kOptimiserPx) << "parameter " << i;
  EXPECT_EQ(r.frames_used, zhang.frames_used);
  EXPECT_EQ(r.observations_used, zhang.observations_used);
  ASSERT_NE(zhang.per_view, nullptr);
  EXPECT_EQ(zhang.observations_used, [&] {
    long n = 0;
    for (const View& v : zhang.per_view->views) n += static_cast<long>(v.pixels.size());
    return n;
  }());
  EXPECT_LT(zhang.frames_used, static_cast<long>(trial->input.Frames().views.size()));
  EXPECT_GT(zhang.frames_used, 0);

  ASSERT_TRUE(SetOption(twin.get(), "init", "dlt", &why)) << why;
  const MethodResult refused = twin->Run(trial->input, nullptr);
  EXPECT_EQ(refused.status, MethodStatus::kFailed);
  EXPECT_NE(refused.message.find("views: init needs an init that solves per-view problems"),
            std::string::npos)
      << refused.message;
}

}  // namespace
}  // namespace calibench
