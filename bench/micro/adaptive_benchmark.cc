// Micro-benchmarks of the hot paths: projection, one thesis run of the adaptive estimator.
// Run: build/bench/calibench_micro_benchmarks  (report medians: --benchmark_repetitions=5
// --benchmark_report_aggregates_only=true).
#include <benchmark/benchmark.h>

#include <string>

#include "adaptive/estimator.h"
#include "camera/camera.h"
#include "sim/measurements.h"
#include "sim/synthetic.h"

namespace calibench {
namespace {

void BM_Project(benchmark::State& state) {
  CameraIntrinsics k;
  k.phi_deg = 87;
  k.k1 = -0.1;
  const auto params = k.Params();
  const Eigen::Vector3d point(0.3, -0.2, 4.0);
  Eigen::Vector2d pixel;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    benchmark::DoNotOptimize(PinholeSkewCamera::Project(params.data(), point.data(), pixel.data()));
    benchmark::DoNotOptimize(pixel);
  }
}
BENCHMARK(BM_Project);

// One full 240 s thesis run (sim 3: moving camera, n = 10, alpha = 1000, continuous source), or
// sim 3 with 30 frames/s held frames (arg 30).
void BM_AdaptiveThesisRun(benchmark::State& state) {
  ThesisSimulation sim = *MakeThesisSimulation(3);
  sim.measurements.sample_rate_hz = static_cast<double>(state.range(0));
  std::string why;
  const auto source = OracleSource::Create(sim.scene, sim.measurements, 1, &why);
  if (!source) {
    state.SkipWithError(why.c_str());
    return;
  }
  const CameraSpec init = ThesisInitialGuess();
  const Vector16d theta0 = ThetaFromCamera(init.intrinsics, init.ParentFromCam().Inverse());
  AdaptiveOptions options;
  options.alpha = sim.alpha;
  long steps = 0;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const AdaptiveSummary summary = RunAdaptiveEstimator(*source, theta0, options);
    steps = summary.iterations;
    benchmark::DoNotOptimize(summary.theta_hat);
  }
  state.counters["steps"] = static_cast<double>(steps);
}
BENCHMARK(BM_AdaptiveThesisRun)->Arg(0)->Arg(30)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace calibench
