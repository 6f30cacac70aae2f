// The rig solve against calibrating its cameras one by one: RefineRig (batch/rig_refine.h) on 24
// synchronised frames of ExampleStereoRig (sim/example_rigs.h: two pinhole-radtan4 cameras, 0.12 m
// baseline; a 6 x 8 board, 0.3 px noise, whole boards), and two RefineCalibration runs
// (batch/refine.h), one per camera, on the same views with the same model. Both start from the
// truth with every pose turned by ~0.5 deg and moved by ~5 mm and compute their covariance; the
// rig's target is at most twice the two single-camera runs together. Counters: solver iterations.
//
// Run: calibench_micro_benchmarks --benchmark_filter='BM_(RigRefine|TwoSingleCameraRefines)'
//      --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "batch/refine.h"
#include "batch/rig_refine.h"
#include "sim/example_rigs.h"
#include "sim/rig_frames.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr int kFrames = 24;

Rigid3 Nudged(const Rigid3& pose) {
  return {ExpSO3(Eigen::Vector3d(0.004, -0.006, 0.005)) * pose.rotation,
          pose.translation + Eigen::Vector3d(0.004, -0.005, 0.003)};
}

struct BenchData {
  CameraRig rig;
  SyntheticRigFrames frames;
  std::vector<Rigid3> start_rig_from_board;
  CameraRig start_rig;
  // Per camera: its views of the frames it saw and their nudged cam_from_board.
  std::vector<std::vector<View>> views;
  std::vector<std::vector<Rigid3>> start_cam_from_board;
};

const BenchData& Data() {
  static const BenchData data = [] {
    BenchData d;
    d.rig = ExampleStereoRig();
    RigFramesOptions o;
    o.num_frames = kFrames;
    o.pixel_sigma_px = 0.3;
    Rng rng(2024);
    d.frames = MakeRigFrames(d.rig, o, &rng);
    d.start_rig = d.rig;
    d.start_rig.cameras[1].cam_from_rig = Nudged(d.rig.cameras[1].cam_from_rig);
    for (const Rigid3& pose : d.frames.rig_from_board)
      d.start_rig_from_board.push_back(Nudged(pose));
    d.views.resize(2), d.start_cam_from_board.resize(2);
    for (size_t f = 0; f < d.frames.frames.size(); ++f) {
      for (int c = 0; c < 2; ++c) {
        const View& view = d.frames.frames[f].views_by_camera[c];
        if (view.points.empty()) continue;
        d.views[c].push_back(view);
        d.start_cam_from_board[c].push_back(
            Nudged(d.rig.cameras[c].cam_from_rig * d.frames.rig_from_board[f]));
      }
    }
    return d;
  }();
  return data;
}

void BM_RigRefine(benchmark::State& state) {
  const BenchData& d = Data();
  RigRefineOptions o;
  o.models = {LensModel::kPinholeRadTan4, LensModel::kPinholeRadTan4};
  long iterations = 0;
  for (auto _ : state) {
    const RigRefineResult r = RefineRig(d.frames.frames, d.start_rig, d.start_rig_from_board, o);
    if (!r.IsUsable()) state.SkipWithError(r.message.c_str());
    iterations = r.iterations;
    benchmark::DoNotOptimize(r.rms_reproj_px);
  }
  state.counters["iterations"] = static_cast<double>(iterations);
  state.counters["frames"] = static_cast<double>(d.frames.frames.size());
}
BENCHMARK(BM_RigRefine)->Unit(benchmark::kMillisecond);

void BM_TwoSingleCameraRefines(benchmark::State& state) {
  const BenchData& d = Data();
  RefineOptions o;
  o.model = LensModel::kPinholeRadTan4;
  o.estimate_skew = false;  // As the rig solve.
  long iterations = 0;
  for (auto _ : state) {
    iterations = 0;
    for (int c = 0; c < 2; ++c) {
      const RefineResult r =
          RefineCalibration(d.views[c], d.rig.cameras[c].intrinsics, d.start_cam_from_board[c], o);
      if (!r.IsUsable()) state.SkipWithError(r.message.c_str());
      iterations += r.iterations;
      benchmark::DoNotOptimize(r.rms_reproj_px);
    }
  }
  state.counters["iterations"] = static_cast<double>(iterations);
}
BENCHMARK(BM_TwoSingleCameraRefines)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace calibench
