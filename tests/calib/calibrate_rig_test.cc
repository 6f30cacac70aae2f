// Calibrating rigs through calib/ (each camera alone, the spanning-tree start, the joint solve) on
// synthetic frames with known truth (sim/example_rigs.h, sim/rig_frames.h): every intrinsic, the
// baseline and the relative rotation within 2 reported std of the truth, counted over frame sets;
// a camera graph in pieces refused by name; the model list checked against the cameras.
#include "calib/calibrate_rig.h"

#include <gtest/gtest.h>

#include "sim/example_rigs.h"
#include "sim/rig_frames.h"

namespace calibench {
namespace {

constexpr double kPixelSigmaPx = 0.3;

// The rig's frames with noise, as calibrate's point input.
RigPointData NoisyFrames(const CameraRig& truth, uint64_t seed, int num_frames) {
  RigFramesOptions options;
  options.num_frames = num_frames;
  options.pixel_sigma_px = kPixelSigmaPx;
  Rng rng(seed);
  const SyntheticRigFrames frames = MakeRigFrames(truth, options, &rng);
  EXPECT_EQ(static_cast<int>(frames.frames.size()), num_frames);
  return RigPointDataFromFrames(frames.frames, truth);
}

// How many estimated figures lie within 2 reported std of the truth, and how many were checked.
struct Coverage {
  int inside = 0, total = 0;
  void Add(double estimate, double truth, double std) {
    ++total;
    if (std::abs(estimate - truth) <= 2.0 * std) ++inside;
  }
};

void AddRig(const CameraRig& truth, const CalibrateRigResult& result, Coverage* coverage) {
  const CameraRig& rig = result.rig.rig;
  for (int c = 0; c < truth.NumCameras(); ++c) {
    const std::array<double, 10> estimate = rig.cameras[c].intrinsics.Params();
    const std::array<double, 10> expected = truth.cameras[c].intrinsics.Params();
    for (int i = 0; i < 10; ++i) {
      const double std = result.rig.intrinsics_std[c][i];
      if (std::isnan(std)) continue;  // Fixed (phi, unused slots).
      coverage->Add(estimate[i], expected[i], std);
    }
    if (c == 0) continue;
    const RigPoseUncertainty& u = result.rig.pose_uncertainty[c];
    coverage->Add(rig.BaselineM(c) * 1000.0, truth.BaselineM(c) * 1000.0, u.baseline_std_mm);
    const Eigen::Vector3d r = rig.RelativeRotationDeg(c), r_true = truth.RelativeRotationDeg(c);
    for (int axis = 0; axis < 3; ++axis) {
      coverage->Add(r[axis], r_true[axis], u.rotation_std_deg[axis]);
    }
  }
}

CalibrateRigOptions OptionsFor(const CameraRig& truth) {
  CalibrateRigOptions options;
  options.models.clear();
  for (const RigCamera& camera : truth.cameras) options.models.push_back(camera.lens_model);
  return options;
}

// Two pinhole-radtan4 cameras, 10 sets of 24 noisy frames (0.3 px): 20 figures a set (8
// intrinsics per camera, the baseline, 3 rotation axes). A Gaussian error falls within 2 std with
// probability 0.954; over 200 figures the binomial std is 1.5 %, so 3 std below is 91 %. The bound,
// 88 %, leaves room for the correlation within a set and for the std's own error (sigma from the
// residuals); a std too small by 1.5x (the real-data case) covers 82 % and fails it.
TEST(CalibrateRigPoints, StereoRigWithinTwoReportedStdOfTheTruth) {
  const CameraRig truth = ExampleStereoRig();
  Coverage coverage;
  for (int set = 0; set < 10; ++set) {
    const CalibrateRigResult result =
        CalibrateRigPoints(NoisyFrames(truth, 9100 + set, 24), OptionsFor(truth));
    ASSERT_TRUE(result.IsUsable()) << result.message;
    EXPECT_EQ(result.rig.rig.NumCameras(), 2);
    // The joint solve fits the noise: RMS per point sqrt(2) sigma.
    EXPECT_NEAR(result.rig.rms_reproj_px, std::sqrt(2.0) * kPixelSigmaPx, 0.05);
    EXPECT_TRUE(result.disagreements.empty());
    ASSERT_EQ(result.epipolar.size(), 1u);
    // Epipolar error of noisy corners: ~sigma (one coordinate across the line, both images).
    EXPECT_LT(result.epipolar[0].rms_px, 2.0 * kPixelSigmaPx);
    AddRig(truth, result, &coverage);
  }
  const double fraction = static_cast<double>(coverage.inside) / coverage.total;
  EXPECT_GE(fraction, 0.88) << coverage.inside << " of " << coverage.total;
  std::cout << "stereo rig: " << coverage.inside << " of " << coverage.total
            << " figures within 2 std\n";
}

// Radtan, double-sphere, radtan; camera 2 shares no frame with camera 0 and is chained through
// camera 1. 4 sets of 36 frames; the same 2-std count.
TEST(CalibrateRigPoints, MixedThreeCameraRigChainedThroughTheWideCamera) {
  const CameraRig truth = ExampleMixedThreeCameraRig();
  Coverage coverage;
  for (int set = 0; set < 4; ++set) {
    const CalibrateRigResult result =
        CalibrateRigPoints(NoisyFrames(truth, 9200 + set, 36), OptionsFor(truth));
    ASSERT_TRUE(result.IsUsable()) << result.message;
    // Camera 2 never shares a frame with camera 0: its start came through camera 1.
    ASSERT_EQ(result.init.parent.size(), 3u);
    EXPECT_EQ(result.init.parent[2], 1);
    for (int other : result.overlaps[2]) EXPECT_NE(other, 0);
    AddRig(truth, result, &coverage);
  }
  const double fraction = static_cast<double>(coverage.inside) / coverage.total;
  EXPECT_GE(fraction, 0.88) << coverage.inside << " of " << coverage.total;
}

// A third camera looking backwards sees only the frames placed in front of it: the graph is in
// two pieces and the error names the camera cut off.
TEST(CalibrateRigPoints, CameraGraphInPiecesIsRefusedNamingTheCamera) {
  CameraRig truth = ExampleStereoRig();
  RigCamera back = truth.cameras[0];
  back.name = "rear";
  const Eigen::Matrix3d r = ExpSO3(Eigen::Vector3d(0, M_PI, 0));
  back.cam_from_rig = {r, -(r * Eigen::Vector3d(0.05, 0, -0.3))};
  truth.cameras.push_back(back);
  RigFramesOptions options;
  options.num_frames = 24;
  options.min_cameras = 1;
  options.pixel_sigma_px = kPixelSigmaPx;
  Rng rng(9300);
  const SyntheticRigFrames frames = MakeRigFrames(truth, options, &rng);
  const CalibrateRigResult result =
      CalibrateRigPoints(RigPointDataFromFrames(frames.frames, truth), OptionsFor(truth));
  EXPECT_EQ(result.status, CalibrateRigResult::Status::kDisconnected);
  EXPECT_NE(result.message.find("rear"), std::string::npos) << result.message;
}

TEST(CalibrateRigPoints, ModelListOfTheWrongLengthIsRefused) {
  const CameraRig truth = ExampleStereoRig();
  CalibrateRigOptions options;
  options.models = {LensModel::kPinholeK2, LensModel::kPinholeK2, LensModel::kPinholeK2};
  const CalibrateRigResult result = CalibrateRigPoints(NoisyFrames(truth, 9400, 12), options);
  EXPECT_FALSE(result.IsUsable());
  EXPECT_NE(result.message.find("3 models for 2 cameras"), std::string::npos) << result.message;
}

}  // namespace
}  // namespace calibench
