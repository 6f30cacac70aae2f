// Renders a stereo rig's calibration images, as a user would photograph a checkerboard with a
// stereo camera, so that `calibench calibrate --images DIR/cam0 --images DIR/cam1` has a rig whose
// truth is known (sim/example_rigs.h ExampleStereoRig: two 640 x 480 pinhole-radtan4 cameras,
// 0.12 m apart). Writes DIR/cam0/frameNN.png, DIR/cam1/frameNN.png (every camera an image of every
// frame; the board may be missing from one of them), DIR/target.yaml (Kalibr checkerboard, 9 x 6
// inner corners, 4 cm) and DIR/truth.txt (the baseline and the relative rotation).
//
//   calibench_example_render_stereo_rig DIR [FRAMES=20] [SEED=7700]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "sim/example_rigs.h"
#include "sim/rig_frames.h"
#include "sim/rig_render.h"
#include "util/random.h"

int main(int argc, char** argv) {
  using namespace calibench;
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " DIR [FRAMES=20] [SEED=7700]\n";
    return 2;
  }
  const std::string dir = argv[1];
  const int num_frames = argc > 2 ? std::atoi(argv[2]) : 20;
  const uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 7700;
  if (num_frames < 3) {
    std::cerr << "FRAMES must be at least 3\n";
    return 2;
  }
  const CameraRig truth = ExampleStereoRig();
  CheckerboardPattern pattern;
  pattern.cols = 9, pattern.rows = 6, pattern.square_m = 0.04;
  std::string why;
  const auto renderer = RigRenderer::Create(truth, pattern, {}, &why);
  if (!renderer) {
    std::cerr << why << "\n";
    return 1;
  }
  RigFramesOptions options;
  options.rows = 6, options.cols = 9, options.spacing_m = 0.04;
  options.num_frames = num_frames;
  options.min_cameras = 1;
  options.edge_margin_px = 60;  // The outer squares inside the image: the detector needs them.
  Rng rng(seed);
  const SyntheticRigFrames frames = MakeRigFrames(truth, options, &rng);
  for (int c = 0; c < truth.NumCameras(); ++c) {
    std::filesystem::create_directories(dir + "/cam" + std::to_string(c));
  }
  Rng noise(seed + 1);
  for (size_t k = 0; k < frames.rig_from_board.size(); ++k) {
    std::vector<GrayImage> images;
    if (!renderer->Render(frames.rig_from_board[k], &noise, &images, &why)) {
      std::cerr << why << "\n";
      return 1;
    }
    for (int c = 0; c < truth.NumCameras(); ++c) {
      char name[64];
      std::snprintf(name, sizeof(name), "/cam%d/frame%02d.png", c, static_cast<int>(k));
      const cv::Mat mat(images[c].height, images[c].width, CV_8UC1, images[c].pixels.data());
      if (!cv::imwrite(dir + name, mat)) {
        std::cerr << dir + name << ": cannot write\n";
        return 1;
      }
    }
  }
  std::ofstream(dir + "/target.yaml")
      << "target_type: 'checkerboard'\ntargetCols: 9\ntargetRows: 6\n"
         "rowSpacingMeters: 0.04\ncolSpacingMeters: 0.04\n";
  const Eigen::Vector3d r = truth.RelativeRotationDeg(1);
  std::ofstream(dir + "/truth.txt")
      << "baseline_mm " << truth.BaselineM(1) * 1000.0 << "\nrotation_vector_deg " << r.x() << " "
      << r.y() << " " << r.z() << "\n";
  std::cout << "wrote " << frames.rig_from_board.size() << " frames of 2 cameras to " << dir
            << "\n";
  return 0;
}
