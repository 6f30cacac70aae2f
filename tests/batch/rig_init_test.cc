#include <gtest/gtest.h>

#include "batch/board_pose.h"
#include "batch/rig_refine.h"
#include "sim/example_rigs.h"
#include "sim/rig_frames.h"

namespace calibench {
namespace {

// Exact pixels and the true intrinsics give board poses exact to ~1e-10 (PnP refined by LM);
// averaging and chaining them loses nothing measurable: the bar is the brief's 1e-6.
constexpr double kExactDeg = 1e-6;
constexpr double kExactM = 1e-6;

struct PerCameraPoses {
  std::vector<std::vector<Rigid3>> cam_from_board;
  std::vector<std::vector<bool>> has_pose;
};
// Each camera's board pose in each frame it saw, by PnP through its own (true) lens.
PerCameraPoses PosesOf(const std::vector<RigFrame>& frames, const CameraRig& rig) {
  PerCameraPoses out;
  const int n = rig.NumCameras();
  out.cam_from_board.assign(n, std::vector<Rigid3>(frames.size()));
  out.has_pose.assign(n, std::vector<bool>(frames.size(), false));
  for (int c = 0; c < n; ++c) {
    for (size_t f = 0; f < frames.size(); ++f) {
      const View& view = frames[f].views_by_camera[c];
      if (view.points.empty()) continue;
      std::string why;
      out.has_pose[c][f] =
          BoardPoseFromIntrinsics(view, rig.cameras[c].intrinsics, &out.cam_from_board[c][f], &why);
    }
  }
  return out;
}

void ExpectRigNear(const CameraRig& got, const CameraRig& truth, double deg, double m) {
  for (int c = 0; c < truth.NumCameras(); ++c) {
    EXPECT_LT(RotationAngleDeg(got.cameras[c].cam_from_rig.rotation,
                               truth.cameras[c].cam_from_rig.rotation),
              deg)
        << "camera " << c;
    EXPECT_LT((got.cameras[c].cam_from_rig.translation - truth.cameras[c].cam_from_rig.translation)
                  .norm(),
              m)
        << "camera " << c;
  }
}

SyntheticRigFrames ExactFrames(const CameraRig& rig, int num_frames, uint64_t seed) {
  RigFramesOptions o;
  o.num_frames = num_frames;
  Rng rng(seed);
  return MakeRigFrames(rig, o, &rng);
}

TEST(RigInit, StereoRigFromExactFrames) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = ExactFrames(truth, 16, 1);
  ASSERT_EQ(s.frames.size(), 16u);
  const PerCameraPoses poses = PosesOf(s.frames, truth);
  CameraRig rig = truth;
  rig.cameras[1].cam_from_rig = Rigid3();
  std::vector<Rigid3> rig_from_board;
  const RigInitSummary summary =
      InitRigExtrinsics(s.frames, poses.cam_from_board, poses.has_pose, &rig, &rig_from_board);
  ASSERT_TRUE(summary.IsUsable()) << summary.message;
  EXPECT_EQ(summary.parent, (std::vector<int>{-1, 0}));
  EXPECT_TRUE(summary.outlier_frames[1].empty());
  ExpectRigNear(rig, truth, kExactDeg, kExactM);
  for (size_t f = 0; f < s.frames.size(); ++f) {
    EXPECT_LT(RotationAngleDeg(rig_from_board[f].rotation, s.rig_from_board[f].rotation),
              kExactDeg);
    EXPECT_LT((rig_from_board[f].translation - s.rig_from_board[f].translation).norm(), kExactM);
  }
}

// One camera's pose flipped by 20 degrees in one frame: dropped as an outlier, the rest exact.
TEST(RigInit, DropsAPoseFarFromTheMedian) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = ExactFrames(truth, 12, 2);
  PerCameraPoses poses = PosesOf(s.frames, truth);
  int bad = -1;
  for (size_t f = 0; f < s.frames.size() && bad < 0; ++f) {
    if (poses.has_pose[0][f] && poses.has_pose[1][f]) bad = static_cast<int>(f);
  }
  ASSERT_GE(bad, 0);
  poses.cam_from_board[1][bad].rotation =
      ExpSO3(Eigen::Vector3d(0, 20.0 * M_PI / 180, 0)) * poses.cam_from_board[1][bad].rotation;
  CameraRig rig = truth;
  std::vector<Rigid3> rig_from_board;
  const RigInitSummary summary =
      InitRigExtrinsics(s.frames, poses.cam_from_board, poses.has_pose, &rig, &rig_from_board);
  ASSERT_TRUE(summary.IsUsable()) << summary.message;
  EXPECT_EQ(summary.outlier_frames[1], std::vector<int>{bad});
  ExpectRigNear(rig, truth, kExactDeg, kExactM);
}

// Camera 2 never shares a frame with camera 0: it is chained through camera 1.
TEST(RigInit, TriRigChainsTheSideCameraThroughTheWideOne) {
  const CameraRig truth = ExampleMixedThreeCameraRig();
  const SyntheticRigFrames s = ExactFrames(truth, 30, 3);
  ASSERT_EQ(s.frames.size(), 30u);
  const PerCameraPoses poses = PosesOf(s.frames, truth);
  CameraRig rig = truth;
  for (RigCamera& camera : rig.cameras) camera.cam_from_rig = Rigid3();
  std::vector<Rigid3> rig_from_board;
  const RigInitSummary summary =
      InitRigExtrinsics(s.frames, poses.cam_from_board, poses.has_pose, &rig, &rig_from_board);
  ASSERT_TRUE(summary.IsUsable()) << summary.message;
  EXPECT_EQ(summary.parent, (std::vector<int>{-1, 0, 1}));
  EXPECT_GT(summary.shared_points[2], 0);
  ExpectRigNear(rig, truth, kExactDeg, kExactM);
}

TEST(RigInit, DisconnectedGraphNamesTheCutOffCameras) {
  const CameraRig truth = ExampleMixedThreeCameraRig();
  SyntheticRigFrames s = ExactFrames(truth, 20, 4);
  for (RigFrame& frame : s.frames) frame.views_by_camera[1] = View();  // The link is gone.
  const PerCameraPoses poses = PosesOf(s.frames, truth);
  CameraRig rig = truth;
  std::vector<Rigid3> rig_from_board;
  const RigInitSummary summary =
      InitRigExtrinsics(s.frames, poses.cam_from_board, poses.has_pose, &rig, &rig_from_board);
  ASSERT_FALSE(summary.IsUsable());
  EXPECT_NE(summary.message.find("cam1, cam2"), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find("cut off"), std::string::npos) << summary.message;
}

TEST(RigInit, RefusesMismatchedInputs) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = ExactFrames(truth, 4, 5);
  CameraRig rig = truth;
  std::vector<Rigid3> rig_from_board;
  const RigInitSummary summary = InitRigExtrinsics(s.frames, {}, {}, &rig, &rig_from_board);
  EXPECT_FALSE(summary.IsUsable());
  EXPECT_NE(summary.message.find("one entry per camera"), std::string::npos);
}

}  // namespace
}  // namespace calibench
