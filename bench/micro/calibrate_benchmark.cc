// Calibration speed per lens family, in one run: `calibrate` (CalibrateFromPoints: the start, then
// ceres with its covariance) on 30, 100 and 300 synthetic views of a 9 x 6 board (54 corners,
// 0.2 px noise, 960 x 600 images, full boards), next to OpenCV's own calibrations of the same
// points: cv::calibrateCamera (radtan data), cv::fisheye::calibrate (equidistant data) and
// cv::omnidir::calibrate (unified data). Every lens has a focal length of 330 px on the axis; the
// boards' centres lie up to 55 degrees from it (the wide families' views).
//
// BM_CeresRefine times the refinement alone from the same start (the truth with poses turned by
// ~1 deg), per family, with the analytic Jacobians (jet = 0) and with the ceres::Jet residual and
// DENSE_SVD covariance that pinhole-equi used before (jet = 1): the Kannala-Brandt slowdown of a
// 29-view, 54-corner stereo fisheye set (cv::fisheye 281.6 ms, ceres 167.2 ms against 11.8 ms for
// pinhole-radtan4) is the 29-view case. Counters: solver iterations and CPU ms per iteration.
//
// Run: calibench_micro_benchmarks
//      --benchmark_filter='BM_(Calibrate/|OpenCv(CalibrateCamera|Fisheye|Omnidir).*/(30|100|300)$)'
//      --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// and the refinement alone (the Kannala-Brandt case before and after):
//      --benchmark_filter='BM_CeresRefine' --benchmark_repetitions=3 ...
#include <benchmark/benchmark.h>

#include <ctime>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>
#include <utility>

#include "batch/refine.h"
#include "batch/zhang.h"
#include "calib/calibrate.h"
#include "sim/synthetic.h"
#include "util/opencv_threads.h"
#include "util/random.h"

namespace calibench {
namespace {

constexpr int kWidth = 960, kHeight = 600;
constexpr double kAxisFocalPx = 330;

// The models timed, by benchmark argument: pinhole-radtan4, then the full model of every family
// but radtan (camera/lens_families.h).
const std::vector<LensModel>& Models() {
  static const std::vector<LensModel> models = [] {
    std::vector<LensModel> m = {LensModel::kPinholeRadTan4};
    for (const LensFamilyInfo& info : LensFamilies()) {
      if (info.family != LensFamily::kRadTan) m.push_back(FullModelOf(info.family));
    }
    return m;
  }();
  return models;
}

// 0 .. Models().size() - 1: the benchmark argument that picks the model.
std::vector<int64_t> ModelIndices() {
  std::vector<int64_t> indices;
  for (size_t i = 0; i < Models().size(); ++i) indices.push_back(static_cast<int64_t>(i));
  return indices;
}

// The family's example lens (LensFamilyInfo::example_lens) at about the same image size.
CameraIntrinsics Truth(LensFamily family) { return ExampleCamera(family, kAxisFocalPx, 482, 297); }

const SyntheticBoardViews& Views(LensFamily family, int views) {
  static std::map<std::pair<int, int>, SyntheticBoardViews> cache;
  const auto key = std::make_pair(static_cast<int>(family), views);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  Rng rng(4321 + views);
  WideBoardOptions o;
  o.rows = 6, o.cols = 9, o.spacing_m = 0.05;
  o.num_views = views;
  o.distance_m = 0.6;
  o.max_angle_deg = 55;
  o.min_visible_fraction = 1.0;  // OpenCV's calibrations need whole boards.
  o.pixel_sigma_px = 0.2;
  o.image_width = kWidth, o.image_height = kHeight;
  return cache[key] = MakeWideBoardViews(Truth(family), o, &rng);
}

PointData AsPointData(const SyntheticBoardViews& data) {
  PointData points;
  points.format = "synthetic";
  points.views = data.views;
  points.image_width = kWidth, points.image_height = kHeight;
  return points;
}

void BM_Calibrate(benchmark::State& state) {
  const LensModel model = Models()[state.range(0)];
  const PointData data = AsPointData(Views(FamilyOf(model), static_cast<int>(state.range(1))));
  CalibrateOptions options;
  options.model = model;
  state.SetLabel(ToString(model));
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const CalibrateReport r = CalibrateFromPoints(data, options);
    if (!r.IsUsable()) state.SkipWithError(r.ceres.message.c_str());
    benchmark::DoNotOptimize(r.camera.intrinsics);
  }
}
BENCHMARK(BM_Calibrate)
    ->ArgsProduct({ModelIndices(), {30, 100, 300}})
    ->Unit(benchmark::kMillisecond);

struct OpenCvPoints {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
};
OpenCvPoints ToOpenCv(const SyntheticBoardViews& data) {
  OpenCvPoints p;
  for (const View& v : data.views) {
    p.object.emplace_back();
    p.image.emplace_back();
    for (size_t i = 0; i < v.points.size(); ++i) {
      p.object.back().emplace_back(v.points[i].x(), v.points[i].y(), 0.f);
      p.image.back().emplace_back(v.pixels[i].x(), v.pixels[i].y());
    }
  }
  return p;
}

void BM_OpenCvCalibrateCamera(benchmark::State& state) {
  const OpenCvPoints p = ToOpenCv(Views(LensFamily::kRadTan, static_cast<int>(state.range(0))));
  UseSequentialOpenCv();
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    cv::Mat k, d;
    std::vector<cv::Mat> r, t;
    const double rms = cv::calibrateCamera(p.object, p.image, cv::Size(kWidth, kHeight), k, d, r, t,
                                           cv::CALIB_FIX_K3 | cv::CALIB_USE_LU);
    benchmark::DoNotOptimize(rms);
  }
}
BENCHMARK(BM_OpenCvCalibrateCamera)->Arg(30)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_OpenCvFisheyeCalibrate(benchmark::State& state) {
  const OpenCvPoints p =
      ToOpenCv(Views(LensFamily::kEquidistant, static_cast<int>(state.range(0))));
  UseSequentialOpenCv();
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    cv::Matx33d k;
    cv::Vec4d d;
    std::vector<cv::Mat> r, t;
    const double rms = cv::fisheye::calibrate(
        p.object, p.image, cv::Size(kWidth, kHeight), k, d, r, t,
        cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
    benchmark::DoNotOptimize(rms);
  }
}
BENCHMARK(BM_OpenCvFisheyeCalibrate)->Arg(30)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_OpenCvOmnidirCalibrate(benchmark::State& state) {
  const SyntheticBoardViews& data = Views(LensFamily::kUnified, static_cast<int>(state.range(0)));
  // cv::omnidir takes double-precision points (CV_64FC3 / CV_64FC2 per view).
  std::vector<cv::Mat> object, image;
  for (const View& v : data.views) {
    cv::Mat o(static_cast<int>(v.points.size()), 1, CV_64FC3), i(o.rows, 1, CV_64FC2);
    for (int j = 0; j < o.rows; ++j) {
      o.at<cv::Vec3d>(j) = cv::Vec3d(v.points[j].x(), v.points[j].y(), 0);
      i.at<cv::Vec2d>(j) = cv::Vec2d(v.pixels[j].x(), v.pixels[j].y());
    }
    object.push_back(o);
    image.push_back(i);
  }
  UseSequentialOpenCv();
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    cv::Mat k, xi, d, idx;
    std::vector<cv::Mat> r, t;
    const double rms = cv::omnidir::calibrate(
        object, image, cv::Size(kWidth, kHeight), k, xi, d, r, t, cv::omnidir::CALIB_FIX_SKEW,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-8), idx);
    state.counters["views_used"] = static_cast<double>(idx.total());
    benchmark::DoNotOptimize(rms);
  }
}
BENCHMARK(BM_OpenCvOmnidirCalibrate)->Arg(30)->Arg(100)->Unit(benchmark::kMillisecond);
// 300 views, one call (hours of CPU: cv::omnidir::calibrate grows as N^4): run it by its own
// filter, 'BM_OpenCvOmnidirCalibrateOnce/300', without repetitions.
void BM_OpenCvOmnidirCalibrateOnce(benchmark::State& state) { BM_OpenCvOmnidirCalibrate(state); }
BENCHMARK(BM_OpenCvOmnidirCalibrateOnce)->Arg(300)->Iterations(1)->Unit(benchmark::kSecond);

// The refinement alone (header comment): args model index, views, jet (0 analytic, 1 ceres::Jet
// with DENSE_SVD covariance), covariance (0: none, the per-iteration figure; 1: as calibrate).
void BM_CeresRefine(benchmark::State& state) {
  const LensModel model = Models()[state.range(0)];
  const SyntheticBoardViews& data = Views(FamilyOf(model), static_cast<int>(state.range(1)));
  std::vector<Rigid3> poses = data.cam_from_board;
  for (Rigid3& p : poses) {
    p.rotation = p.rotation * ExpSO3(Eigen::Vector3d(0.012, -0.01, 0.008));
    p.translation += Eigen::Vector3d(0.005, -0.005, 0.005);
  }
  RefineOptions options;
  options.model = model;
  options.estimate_skew = false;
  options.autodiff = state.range(2) != 0;
  options.compute_covariance = state.range(3) != 0;
  state.SetLabel(std::string(ToString(model)) + (options.autodiff ? " jet" : " analytic") +
                 (options.compute_covariance ? " +cov" : ""));
  long iterations = 0;
  double cpu_ms = 0;      // The process's CPU time over the solves (the machine may be shared).
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const std::clock_t start = std::clock();
    const RefineResult r = RefineCalibration(data.views, Truth(FamilyOf(model)), poses, options);
    cpu_ms += 1e3 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    if (!r.IsUsable()) state.SkipWithError(r.message.c_str());
    iterations += r.iterations;
    benchmark::DoNotOptimize(r.intrinsics);
  }
  state.counters["iterations"] = static_cast<double>(iterations) /
                                 static_cast<double>(std::max<int64_t>(1, state.iterations()));
  state.counters["cpu_ms_per_iteration"] = cpu_ms / static_cast<double>(std::max(1L, iterations));
}
BENCHMARK(BM_CeresRefine)
    ->ArgsProduct({ModelIndices(), {29, 100}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace calibench
