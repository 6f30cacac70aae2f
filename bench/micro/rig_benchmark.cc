// The rig's target: a 2-camera calibration of 24 frames takes at most 2x the two single-camera
// calibrations of the same cameras. Two pairs of benchmarks, one run:
//
// BM_CalibrateRigPoints / BM_TwoCameraCalibrations: the whole calibration a user runs, on 24
// RENDERED frames of ExampleStereoRig (sim/example_rigs.h: two 640 x 480 pinhole-radtan4 cameras,
// 0.12 m baseline) seeing a 9 x 6 checkerboard of 0.04 m squares (sim/rig_render.h RigRenderer, as
// tests/calib/calibrate_rig_rendered_test.cc draws them: MakeRigFrames with min_cameras 1 and a
// 60 px edge margin, so some frames show the whole board to one camera only). The images are
// written once to a folder under the temp directory and their corners found once by
// calibrate --images' detector (calib/image_points.h LoadImagePoints, per camera its frames'
// files, as CalibrateRigImages does), outside the timed loop: detection costs the same for the
// rig and for the two cameras and would hide the ratio. The corner re-fits through the lens
// (--corner-iterations) are not timed either. Timed, from the detected corners, with each side's
// defaults (what `calibench calibrate` runs after detection):
//   BM_CalibrateRigPoints: CalibrateRigPoints (calib/calibrate_rig.h), models {pinhole-radtan4,
//     pinhole-radtan4}: each camera alone (zhang + ceres with covariance), the rig's start, the
//     joint solve with its covariance, the rig's leave-one-frame-out jackknife (kAuto: 24 more
//     joint solves for these 24 frames), the epipolar and disagreement checks;
//   BM_TwoCameraCalibrations: CalibratePoints once per camera with its default jackknife (kAuto:
//     24 leave-one-view-out refits each): `calibench calibrate --images L`, then R.
// The same without the jackknife on either side (--jackknife off): BM_CalibrateRigPointsNoJackknife
// and BM_TwoCameraCalibrationsNoJackknife (CalibrateFromPoints); BM_RigJackknife: JackknifeRig
// alone, on the joint solve of a CalibrateRigPoints run.
// Counters: the views per camera and the frames both saw, solver iterations (the rig's: its joint
// solve's, camera_iterations the cameras' alone summed; the two calibrations': summed), the rig
// jackknife's refits (0: not run).
//
// BM_RigRefine / BM_TwoSingleCameraRefines: the solvers alone, on oracle frames: RefineRig
// (batch/rig_refine.h) on 24 synchronised frames of ExampleStereoRig (a 6 x 8 board, 0.3 px noise,
// whole boards), and two RefineCalibration runs (batch/refine.h), one per camera, on the same
// views with the same model. Both start from the truth with every pose turned by ~0.5 deg and
// moved by ~5 mm and compute their covariance.
//
// Run: calibench_micro_benchmarks --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//      --benchmark_filter='BM_(CalibrateRigPoints|TwoCameraCalibrations|RigRefine|TwoSingleCameraRefines)'
// and the breakdown: the same with --benchmark_filter='BM_Breakdown'.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "batch/jackknife.h"
#include "batch/refine.h"
#include "batch/rig_refine.h"
#include "calib/calibrate.h"
#include "calib/calibrate_rig.h"
#include "calib/image_points.h"
#include "sim/example_rigs.h"
#include "sim/rig_frames.h"
#include "sim/rig_render.h"
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
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
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
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
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

// 24 rendered frames of the stereo rig, their corners detected once (header comment).
struct RenderedRigData {
  RigPointData data;
  std::string error;  // Non-empty: the setup failed (the benchmarks skip with it).
};

RenderedRigData MakeRenderedRigData() {
  namespace fs = std::filesystem;
  RenderedRigData d;
  const CameraRig truth = ExampleStereoRig();
  CheckerboardPattern pattern;
  pattern.cols = 9, pattern.rows = 6, pattern.square_m = 0.04;
  const auto renderer = RigRenderer::Create(truth, pattern, {}, &d.error);
  if (!renderer) return d;
  CalibrationTarget target;
  target.type = CalibrationTarget::Type::kCheckerboard;
  target.cols = 9, target.rows = 6, target.row_spacing_m = target.col_spacing_m = 0.04;
  RigFramesOptions frames_options;
  frames_options.rows = 6, frames_options.cols = 9, frames_options.spacing_m = 0.04;
  frames_options.num_frames = kFrames;
  frames_options.min_cameras = 1;
  frames_options.edge_margin_px = 60;  // The outer squares inside the image too.
  Rng rng(7700);
  const SyntheticRigFrames frames = MakeRigFrames(truth, frames_options, &rng);
  if (frames.frames.size() != static_cast<size_t>(kFrames)) {
    d.error = "MakeRigFrames drew " + std::to_string(frames.frames.size()) + " frames";
    return d;
  }
  const int num_cameras = truth.NumCameras();
  const fs::path dir =
      fs::temp_directory_path() / ("calibench_rig_benchmark_" + std::to_string(getpid()));
  fs::remove_all(dir);
  std::vector<std::string> folders, files;
  for (int c = 0; c < num_cameras; ++c) {
    folders.push_back((dir / ("cam" + std::to_string(c))).string());
    fs::create_directories(folders.back());
  }
  Rng noise(7800);
  for (int k = 0; k < kFrames && d.error.empty(); ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame%02d.png", k);
    files.push_back(name);
    std::vector<GrayImage> images;
    if (!renderer->Render(frames.rig_from_board[k], &noise, &images, &d.error)) break;
    for (int c = 0; c < num_cameras; ++c) {
      const cv::Mat mat(images[c].height, images[c].width, CV_8UC1, images[c].pixels.data());
      if (!cv::imwrite(folders[c] + "/" + name, mat)) d.error = "cannot write " + folders[c];
    }
  }
  // Each camera's corners as calibrate --images finds them for a radtan model (no camera yet:
  // the first pass), every camera an image of every frame; view_of_frame by file name.
  d.data.view_of_frame.assign(kFrames, std::vector<int>(num_cameras, -1));
  d.data.frame_names = files;
  for (int c = 0; c < num_cameras && d.error.empty(); ++c) {
    ImagePointOptions images;
    images.lens = LensFamily::kRadTan;
    images.files = files;
    images.threads = 2;
    PointData points;
    ImageFolderReport report;
    std::vector<int> used_index;
    if (!LoadImagePoints(folders[c], target, &points, &report, &used_index, &d.error, images)) {
      break;
    }
    for (size_t v = 0; v < points.views.size(); ++v) {
      const std::string& file = report.images[used_index[v]].file;
      const auto it = std::find(files.begin(), files.end(), file);
      if (it != files.end()) d.data.view_of_frame[it - files.begin()][c] = static_cast<int>(v);
    }
    d.data.cameras.push_back(std::move(points));
    d.data.camera_names.push_back(folders[c]);
  }
  fs::remove_all(dir);
  return d;
}

const RenderedRigData& Rendered() {
  static const RenderedRigData data = MakeRenderedRigData();
  return data;
}

// The rig's options: both cameras pinhole-radtan4, every other option its default (as calibrate
// --model pinhole-radtan4 with two --images).
CalibrateRigOptions StereoRigOptions() {
  CalibrateRigOptions o;
  o.models = {LensModel::kPinholeRadTan4, LensModel::kPinholeRadTan4};
  return o;
}

void BM_CalibrateRigPoints(benchmark::State& state) {
  const RenderedRigData& d = Rendered();
  if (!d.error.empty()) {
    state.SkipWithError(d.error.c_str());
    return;
  }
  const CalibrateRigOptions o = StereoRigOptions();
  long rig_iterations = 0, camera_iterations = 0, jackknife_refits = 0;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const CalibrateRigResult r = CalibrateRigPoints(d.data, o);
    if (!r.IsUsable()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
    rig_iterations = r.rig.iterations;
    jackknife_refits = r.jackknife ? r.jackknife->num_frames : 0;
    camera_iterations = 0;
    for (const CalibrateResult& camera : r.cameras) {
      camera_iterations += camera.calibration.ceres.iterations;
    }
    benchmark::DoNotOptimize(r.rig.rms_reproj_px);
  }
  state.counters["iterations"] = static_cast<double>(rig_iterations);
  state.counters["camera_iterations"] = static_cast<double>(camera_iterations);
  state.counters["jackknife_refits"] = static_cast<double>(jackknife_refits);
  state.counters["views0"] = static_cast<double>(d.data.cameras[0].views.size());
  state.counters["views1"] = static_cast<double>(d.data.cameras[1].views.size());
  int shared = 0;
  for (const std::vector<int>& views : d.data.view_of_frame)
    shared += views[0] >= 0 && views[1] >= 0;
  state.counters["shared_frames"] = shared;
}
BENCHMARK(BM_CalibrateRigPoints)->Unit(benchmark::kMillisecond);

void BM_TwoCameraCalibrationsNoJackknife(benchmark::State& state) {
  const RenderedRigData& d = Rendered();
  if (!d.error.empty()) {
    state.SkipWithError(d.error.c_str());
    return;
  }
  CalibrateOptions o;
  o.model = LensModel::kPinholeRadTan4;
  long iterations = 0;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    iterations = 0;
    for (const PointData& camera : d.data.cameras) {
      const CalibrateReport r = CalibrateFromPoints(camera, o);
      if (!r.IsUsable()) state.SkipWithError(r.ceres.message.c_str());
      iterations += r.ceres.iterations;
      benchmark::DoNotOptimize(r.ceres.rms_reproj_px);
    }
  }
  state.counters["iterations"] = static_cast<double>(iterations);
}
BENCHMARK(BM_TwoCameraCalibrationsNoJackknife)->Unit(benchmark::kMillisecond);

void BM_CalibrateRigPointsNoJackknife(benchmark::State& state) {
  const RenderedRigData& d = Rendered();
  if (!d.error.empty()) {
    state.SkipWithError(d.error.c_str());
    return;
  }
  CalibrateRigOptions o = StereoRigOptions();
  o.jackknife = CalibrateOptions::Jackknife::kOff;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const CalibrateRigResult r = CalibrateRigPoints(d.data, o);
    if (!r.IsUsable()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
    benchmark::DoNotOptimize(r.rig.rms_reproj_px);
  }
}
BENCHMARK(BM_CalibrateRigPointsNoJackknife)->Unit(benchmark::kMillisecond);

void BM_RigJackknife(benchmark::State& state) {
  const RenderedRigData& d = Rendered();
  if (!d.error.empty()) {
    state.SkipWithError(d.error.c_str());
    return;
  }
  CalibrateRigOptions o = StereoRigOptions();
  o.jackknife = CalibrateOptions::Jackknife::kOff;
  const CalibrateRigResult full = CalibrateRigPoints(d.data, o);
  if (!full.IsUsable()) {
    state.SkipWithError(full.message.c_str());
    return;
  }
  RigJackknifeOptions jack;  // As SolveRigFrom (calibrate_rig.cc) builds it.
  jack.refine.models = o.models;
  jack.refine.estimate_skew = o.estimate_skew;
  long frames = 0, iterations = 0;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const RigJackknifeResult r = JackknifeRig(full.frames, full.rig, jack);
    if (!r.IsUsable()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
    frames = r.num_frames;
    iterations = r.iterations;
    benchmark::DoNotOptimize(r.pose);
  }
  state.counters["refits"] = static_cast<double>(frames);
  state.counters["iterations"] = static_cast<double>(iterations);  // Of every refit.
}
BENCHMARK(BM_RigJackknife)->Unit(benchmark::kMillisecond);

void BM_TwoCameraCalibrations(benchmark::State& state) {
  const RenderedRigData& d = Rendered();
  if (!d.error.empty()) {
    state.SkipWithError(d.error.c_str());
    return;
  }
  CalibrateOptions o;
  o.model = LensModel::kPinholeRadTan4;
  o.jackknife = CalibrateOptions::Jackknife::kAuto;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    for (const PointData& camera : d.data.cameras) {
      const CalibrateResult r = CalibratePoints(camera, o);
      if (!r.IsUsable() || !r.calibration.jackknife) state.SkipWithError("no jackknife");
      benchmark::DoNotOptimize(r.calibration.ceres.rms_reproj_px);
    }
  }
}
BENCHMARK(BM_TwoCameraCalibrations)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace calibench
