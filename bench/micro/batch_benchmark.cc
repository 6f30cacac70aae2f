// Batch calibration speed: Ceres refinement vs cv::calibrateCamera on the same data, in one run.
// 50 views of a 10 x 15 board (150 points per view), sigma = 0.5 px, pinhole + k1, k2 (no skew:
// the model OpenCV estimates). OpenCV starts from scratch (its own closed-form initialisation);
// Ceres from a start as rough as a closed-form one: focal lengths 2% off, principal point 4 px off,
// no distortion, every board pose rotated by ~1 degree and shifted by 1 cm.
#include <benchmark/benchmark.h>

#include <map>

#include "batch/refine.h"
#include "batch/zhang.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

const SyntheticBoardViews& Data(int views) {
  static std::map<int, SyntheticBoardViews> cache;
  auto it = cache.find(views);
  if (it != cache.end()) return it->second;
  Rng rng(1234);
  SyntheticBoardOptions o;
  o.rows = 10;
  o.cols = 15;
  o.spacing_m = 0.025;
  o.num_views = views;
  o.distance_m = 0.7;
  o.pixel_sigma_px = 0.5;
  const CameraIntrinsics truth{812, 805, 90, 322, 236, -0.21, 0.08};
  return cache[views] = MakeBoardViews(truth, o, &rng);
}

void BM_OpenCvCalibrateCamera(benchmark::State& state) {
  const SyntheticBoardViews& data = Data(static_cast<int>(state.range(0)));
  ZhangOptions options;
  options.model = LensModel::kPinholeK2;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const ZhangResult r = CalibrateZhang(data.views, options);
    benchmark::DoNotOptimize(r.intrinsics);
  }
}
BENCHMARK(BM_OpenCvCalibrateCamera)->Arg(10)->Arg(20)->Arg(50)->Unit(benchmark::kMillisecond);

void BM_CeresCalibration(benchmark::State& state) {
  const SyntheticBoardViews& data = Data(static_cast<int>(state.range(0)));
  CameraIntrinsics start{812 * 1.02, 805 * 0.98, 90, 318, 240, 0, 0};
  std::vector<Rigid3> poses = data.cam_from_board;
  for (Rigid3& p : poses) {
    p.rotation = p.rotation * ExpSO3(Eigen::Vector3d(0.012, -0.01, 0.008));
    p.translation += Eigen::Vector3d(0.01, -0.01, 0.01);
  }
  RefineOptions options;
  options.model = LensModel::kPinholeK2;
  options.estimate_skew = false;
  options.compute_covariance = false;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const RefineResult r = RefineCalibration(data.views, start, poses, options);
    if (!r.IsUsable()) state.SkipWithError(r.message.c_str());
    benchmark::DoNotOptimize(r.intrinsics);
  }
}
BENCHMARK(BM_CeresCalibration)->Arg(10)->Arg(20)->Arg(50)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace calibench

BENCHMARK_MAIN();
