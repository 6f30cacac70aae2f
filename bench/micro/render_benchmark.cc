// Rendering and detection speed: one 640x480 frame of a 6x5 AprilTag grid, 4x4 supersampling at
// edges; raw AprilTag 3 detection of that frame through the wrapper and through the C API.
#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <benchmark/benchmark.h>

#include "core/render.h"
#include "core/synthetic.h"
#include "detect/apriltag_detector.h"

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

}  // namespace
}  // namespace calibench
