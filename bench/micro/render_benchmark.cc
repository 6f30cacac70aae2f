// Rendering and detection speed: one 640x480 frame of a 6x5 AprilTag grid, 4x4 supersampling at
// edges, through a radtan lens (the ray table), a pinhole (rays on the fly) and a 190 deg
// double-sphere lens (stereographic rays); raw AprilTag 3 detection of that frame through the
// wrapper and through the C API.
// The rendered pipeline of the default sweeps per frame (BM_RigPipeline: render + detect + refine
// + match, configs/rig.yaml's options, frames cycling through the trial's 240 poses; /0
// without the prediction of missed tags, frame_detector.h) against the raw C API call on the same
// frames at quad_decimate 1 (BM_RigDetectCApi/1) and 2 (/2): the target is BM_RigPipeline <= 1.5 x
// BM_RigDetectCApi/1 (docs/results/detection.md, "Cost of the rendered pipeline").
#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>

#include "bench/config/config_io.h"
#include "detect/apriltag_detector.h"
#include "detect/frame_detector.h"
#include "detect/rendered_source.h"
#include "sim/render.h"
#include "sim/scene_renderer.h"
#include "sim/synthetic.h"

namespace calibench {
namespace {

BoardView GridView() {
  BoardView b = SixByFiveTagGrid();
  b.cam_from_board = FacingBoardPose({0.3, -0.2, 0.1}, {0.15, 0.125, 0}, {0, 0, 0.5});
  return b;
}

const CameraIntrinsics kCamera{600, 600, 90, 319.5, 239.5, -0.1, 0.02};

// One frame of a camera whose renderer (pixel-corner ray table) already exists: the per-frame cost
// of a rendered scenario.
void BM_RenderFrame(benchmark::State& state) {
  const std::vector<BoardView> boards = {GridView()};
  const auto renderer = FrameRenderer::Create(kCamera, RenderOptions(), nullptr);
  GrayImage img;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    renderer->Render(boards, nullptr, &img, nullptr);
    benchmark::DoNotOptimize(img.pixels.data());
  }
}
BENCHMARK(BM_RenderFrame)->Unit(benchmark::kMillisecond);

// The same frame without distortion: the rays are affine in the pixel, computed on the fly.
void BM_RenderFrameUndistorted(benchmark::State& state) {
  const std::vector<BoardView> boards = {GridView()};
  const CameraIntrinsics pinhole{600, 600, 90, 319.5, 239.5};
  const auto renderer = FrameRenderer::Create(pinhole, RenderOptions(), nullptr);
  GrayImage img;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    renderer->Render(boards, nullptr, &img, nullptr);
    benchmark::DoNotOptimize(img.pixels.data());
  }
}
BENCHMARK(BM_RenderFrameUndistorted)->Unit(benchmark::kMillisecond);

// The grid through a 190 deg double-sphere lens (xi 0.6, alpha 0.6, 640 x 480, 95 deg at 235 px
// from the centre), seen 60 deg off the axis: the table holds stereographic rays.
void BM_RenderFrameDoubleSphere(benchmark::State& state) {
  CameraIntrinsics lens{207, 207, 90, 319.5, 239.5};
  lens.family = LensFamily::kDoubleSphere;
  lens.xi = 0.6;
  lens.alpha = 0.6;
  BoardView board = SixByFiveTagGrid();
  board.cam_from_board = FacingBoardPoseAlong({0.3, -0.2, 0.1}, {0.15, 0.125, 0},
                                              {std::sin(1.05), 0, std::cos(1.05)}, 0.35);
  const auto renderer = FrameRenderer::Create(lens, RenderOptions(), nullptr);
  GrayImage img;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    renderer->Render({board}, nullptr, &img, nullptr);
    benchmark::DoNotOptimize(img.pixels.data());
  }
}
BENCHMARK(BM_RenderFrameDoubleSphere)->Unit(benchmark::kMillisecond);

// The one-time cost of a camera: undistorting the rays of all pixel corners.
void BM_CreateRenderer(benchmark::State& state) {
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    benchmark::DoNotOptimize(FrameRenderer::Create(kCamera, RenderOptions(), nullptr));
  }
}
BENCHMARK(BM_CreateRenderer)->Unit(benchmark::kMillisecond);

void BM_DetectWrapper(benchmark::State& state) {
  GrayImage img;
  RenderFrame(kCamera, {GridView()}, RenderOptions(), nullptr, &img, nullptr);
  const auto detector = AprilTagDetector::Create({}, nullptr);
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    benchmark::DoNotOptimize(detector->Detect(img));
  }
}
BENCHMARK(BM_DetectWrapper)->Unit(benchmark::kMillisecond);

void BM_DetectCApi(benchmark::State& state) {
  GrayImage img;
  RenderFrame(kCamera, {GridView()}, RenderOptions(), nullptr, &img, nullptr);
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(detector, family, 1);
  detector->quad_decimate = 1;
  image_u8_t view{img.width, img.height, img.width, img.pixels.data()};
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    zarray_t* detections = apriltag_detector_detect(detector, &view);
    benchmark::DoNotOptimize(detections);
    apriltag_detections_destroy(detections);
  }
  apriltag_detector_destroy(detector);
  tag36h11_destroy(family);
}
BENCHMARK(BM_DetectCApi)->Unit(benchmark::kMillisecond);

// The rig scenario of the default sweeps, rendered as its trial 0 renders it.
struct Rig {
  ScenarioConfig scenario;
  SceneTruth scene;
  std::vector<AprilGrid> grids;  // The renderer keeps a reference.
  std::unique_ptr<SceneRenderer> renderer;
  std::vector<double> times;
  static const Rig& Get() {
    static const Rig rig = [] {
      Rig r;
      RunConfig config;
      std::string why;
      if (!LoadRunConfig(std::string(CALIBENCH_SOURCE_DIR) + "/configs/rig.yaml", &config, &why)) {
        std::fprintf(stderr, "rig.yaml: %s\n", why.c_str());
        std::abort();
      }
      r.scenario = config.scenarios.at(0);
      r.scene = r.scenario.MakeScene();
      r.grids = r.scenario.points.AprilGrids();
      r.renderer =
          SceneRenderer::Create(r.scene, r.grids, r.scenario.RenderingOptions().render, &why);
      r.times = FrameTimes(r.scenario.measurements.sample_rate_hz, r.scenario.duration_s);
      return r;
    }();
    return rig;
  }
};

void BM_RigPipeline(benchmark::State& state) {
  const Rig& rig = Rig::Get();
  FrameDetectorOptions options = rig.scenario.RenderingOptions().detection;
  options.predict_missing_tags = state.range(0) != 0;
  const auto detector = FrameDetector::Create(rig.scenario.points.AprilGrids(), options, nullptr);
  GrayImage image;
  std::vector<BoardView> views;
  size_t k = 0;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    const int frame = static_cast<int>(k++ % rig.times.size());
    rig.renderer->Render(rig.times[frame], 1, frame, &image, &views, nullptr);
    DetectionCounts counts;
    benchmark::DoNotOptimize(detector->Detect(image, &counts));
  }
}
BENCHMARK(BM_RigPipeline)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The raw C API on the rig's frames (rendered once, outside the timing).
void BM_RigDetectCApi(benchmark::State& state) {
  const Rig& rig = Rig::Get();
  std::vector<GrayImage> frames(16);
  std::vector<BoardView> views;
  for (size_t f = 0; f < frames.size(); ++f) {
    const int frame = static_cast<int>(f * rig.times.size() / frames.size());
    rig.renderer->Render(rig.times[frame], 1, frame, &frames[f], &views, nullptr);
  }
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(detector, family, 1);
  detector->quad_decimate = static_cast<float>(state.range(0));
  size_t k = 0;
  for (auto _ : state) {  // NOLINT(clang-analyzer-deadcode.DeadStores)
    GrayImage& img = frames[k++ % frames.size()];
    image_u8_t view{img.width, img.height, img.width, img.pixels.data()};
    zarray_t* detections = apriltag_detector_detect(detector, &view);
    benchmark::DoNotOptimize(detections);
    apriltag_detections_destroy(detections);
  }
  apriltag_detector_destroy(detector);
  tag36h11_destroy(family);
}
BENCHMARK(BM_RigDetectCApi)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace calibench
