// Rigs calibrated from rendered images through calibrate's image path (calib/rig_images.h pairs the
// folders, calib/calibrate_rig.h calibrates): a 2-camera pinhole-radtan stereo pair on a
// checkerboard and a 3-camera rig mixing pinhole-radtan with a double-sphere fisheye on an
// AprilGrid, with partial overlap (camera 2 never shares a frame with camera 0). Every intrinsic,
// the baseline and the relative rotation within 2 reported std of the truth, counted over frame
// sets as the wide-lens test counts (label rendered-rig).
#include <gtest/gtest.h>

#include <filesystem>

#include "calib/calibrate_rig.h"
#include "calib/rig_images.h"
#include "sim/example_rigs.h"
#include "sim/rig_frames.h"
#include "sim/rig_render.h"
#include "tests/common/rendered_folder.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

struct Coverage {
  int inside = 0, total = 0;
  std::vector<std::string> outside;
  void Add(const std::string& name, double estimate, double truth, double std) {
    ++total;
    if (std::abs(estimate - truth) <= 2.0 * std) {
      ++inside;
    } else {
      outside.push_back(name + " off by " + std::to_string((estimate - truth) / std) + " std");
    }
  }
};

void AddRig(const CameraRig& truth, const CalibrateRigResult& result, Coverage* coverage) {
  const CameraRig& rig = result.rig.rig;
  for (int c = 0; c < truth.NumCameras(); ++c) {
    const std::array<double, 10> estimate = rig.cameras[c].intrinsics.Params();
    const std::array<double, 10> expected = truth.cameras[c].intrinsics.Params();
    const auto& names = ParamNames(truth.cameras[c].intrinsics.family);
    for (int i = 0; i < 10; ++i) {
      const double std = result.rig.intrinsics_std[c][i];
      if (std::isnan(std)) continue;
      coverage->Add("cam" + std::to_string(c) + " " + names[i], estimate[i], expected[i], std);
    }
    if (c == 0) continue;
    const RigPoseUncertainty& u = result.rig.pose_uncertainty[c];
    coverage->Add("cam" + std::to_string(c) + " baseline", rig.BaselineM(c) * 1000.0,
                  truth.BaselineM(c) * 1000.0, u.baseline_std_mm);
    const Eigen::Vector3d r = rig.RelativeRotationDeg(c), r_true = truth.RelativeRotationDeg(c);
    for (int axis = 0; axis < 3; ++axis) {
      coverage->Add("cam" + std::to_string(c) + " rotation " + "xyz"[axis], r[axis], r_true[axis],
                    u.rotation_std_deg[axis]);
    }
  }
}

// Renders `poses` of the rig's target into DIR/cam<c>/frame<k>.png (every camera an image of every
// frame, as a real rig takes them), pairs the folders and calibrates.
CalibrateRigResult RenderAndCalibrate(const std::string& dir, const CameraRig& truth,
                                      const RigRenderer& renderer, const CalibrationTarget& target,
                                      const std::vector<Rigid3>& poses, uint64_t seed) {
  fs::remove_all(dir);
  std::vector<std::string> sources;
  for (int c = 0; c < truth.NumCameras(); ++c) {
    sources.push_back(dir + "/cam" + std::to_string(c));
    fs::create_directories(sources.back());
  }
  Rng rng(seed);
  for (size_t k = 0; k < poses.size(); ++k) {
    std::vector<GrayImage> images;
    std::string why;
    EXPECT_TRUE(renderer.Render(poses[k], &rng, &images, &why)) << why;
    for (int c = 0; c < truth.NumCameras(); ++c) {
      char name[32];
      std::snprintf(name, sizeof(name), "/frame%02d.png", static_cast<int>(k));
      EXPECT_TRUE(WritePng(sources[c] + name, &images[c]));
    }
  }
  const RigImageSummary pairing = PairRigImages(sources);
  EXPECT_TRUE(pairing.ok) << pairing.error;
  EXPECT_EQ(pairing.frames.size(), poses.size());
  std::vector<RigCameraImages> cameras(truth.NumCameras());
  for (int c = 0; c < truth.NumCameras(); ++c) {
    cameras[c].source = sources[c];
    cameras[c].dir = sources[c];
    for (const RigImageFrame& frame : pairing.frames) {
      cameras[c].files_by_frame.push_back(fs::path(frame.path_by_camera[c]).filename().string());
    }
  }
  CalibrateRigOptions options;
  options.models.clear();
  for (const RigCamera& camera : truth.cameras) options.models.push_back(camera.lens_model);
  ImagePointOptions images;
  images.threads = 2;
  return CalibrateRigImages(cameras, target, images, options);
}

// 3 sets of 20 frames of the stereo pair (some frames seen by one camera only: the board must be
// whole in a camera for the checkerboard detector). 20 figures a set; >= 50 of 60 within 2 std (a
// Gaussian count: 57.2 expected, binomial std 1.6; the bound is 4.5 std below it, as the rendered
// corners' small bias and sigma from the residuals make the std approximate).
TEST(CalibrateRigImages, RenderedStereoPairWithinTwoReportedStd) {
  const CameraRig truth = ExampleStereoRig();
  CheckerboardPattern pattern;
  pattern.cols = 9, pattern.rows = 6, pattern.square_m = 0.04;
  std::string why;
  const auto renderer = RigRenderer::Create(truth, pattern, {}, &why);
  ASSERT_TRUE(renderer) << why;
  CalibrationTarget target;
  target.type = CalibrationTarget::Type::kCheckerboard;
  target.cols = 9, target.rows = 6, target.row_spacing_m = target.col_spacing_m = 0.04;
  Coverage coverage;
  for (int set = 0; set < 3; ++set) {
    RigFramesOptions frames_options;
    frames_options.rows = 6, frames_options.cols = 9, frames_options.spacing_m = 0.04;
    frames_options.num_frames = 20;
    frames_options.min_cameras = 1;
    frames_options.edge_margin_px = 60;  // The outer squares inside the image too.
    Rng rng(7700 + set);
    const SyntheticRigFrames frames = MakeRigFrames(truth, frames_options, &rng);
    ASSERT_EQ(frames.frames.size(), 20u);
    const CalibrateRigResult result =
        RenderAndCalibrate(::testing::TempDir() + "/rendered_stereo", truth, *renderer, target,
                           frames.rig_from_board, 7800 + set);
    ASSERT_TRUE(result.IsUsable()) << result.message;
    EXPECT_LT(result.rig.rms_reproj_px, 0.1);  // Rendered corners: ~0.02-0.05 px.
    AddRig(truth, result, &coverage);
  }
  EXPECT_GE(coverage.inside, coverage.total - 10) << ::testing::PrintToString(coverage.outside);
  std::cout << "rendered stereo: " << coverage.inside << " of " << coverage.total
            << " within 2 std\n";
}

// 2 sets of 30 frames of the 3-camera rig on a 6 x 6 AprilGrid: partial boards (the grid's tags
// detected one by one), camera 2 chained through the fisheye. >= 90 % within 2 std.
TEST(CalibrateRigImages, RenderedMixedThreeCameraRigWithinTwoReportedStd) {
  const CameraRig truth = ExampleMixedThreeCameraRig();
  AprilGrid grid;
  grid.tag_rows = 6, grid.tag_cols = 6, grid.tag_size_m = 0.05, grid.tag_spacing = 0.3;
  std::string why;
  const auto renderer = RigRenderer::Create(truth, grid, {}, &why);
  ASSERT_TRUE(renderer) << why;
  CalibrationTarget target;
  target.type = CalibrationTarget::Type::kAprilGrid;
  target.grid = grid;
  const double extent = grid.tag_cols * grid.Pitch() - grid.Pitch() + grid.tag_size_m;
  Coverage coverage;
  for (int set = 0; set < 2; ++set) {
    RigFramesOptions frames_options;
    frames_options.rows = 5, frames_options.cols = 5, frames_options.spacing_m = extent / 4;
    frames_options.num_frames = 30;
    frames_options.whole_board = false;
    frames_options.min_visible_fraction = 0.5;
    Rng rng(7900 + set);
    const SyntheticRigFrames frames = MakeRigFrames(truth, frames_options, &rng);
    ASSERT_EQ(frames.frames.size(), 30u);
    const CalibrateRigResult result =
        RenderAndCalibrate(::testing::TempDir() + "/rendered_mixed", truth, *renderer, target,
                           frames.rig_from_board, 8000 + set);
    ASSERT_TRUE(result.IsUsable()) << result.message;
    ASSERT_EQ(result.init.parent.size(), 3u);
    EXPECT_EQ(result.init.parent[2], 1);
    AddRig(truth, result, &coverage);
  }
  EXPECT_GE(coverage.inside, 0.9 * coverage.total) << ::testing::PrintToString(coverage.outside);
  std::cout << "rendered mixed rig: " << coverage.inside << " of " << coverage.total
            << " within 2 std\n";
}

}  // namespace
}  // namespace calibench
