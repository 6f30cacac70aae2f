#include "batch/stereo_opencv.h"

#include <gtest/gtest.h>

#include <cmath>

#include "batch/rig_refine.h"
#include "sim/example_rigs.h"
#include "sim/rig_frames.h"

namespace calibench {
namespace {

// Exact corners: OpenCV's LM (EPS 1e-12) stops within ~1e-7 of the truth on these rigs.
// cv::stereoCalibrate takes float pixels: rounding 500 px to float32 (ulp 6.1e-5 px) leaves a
// uniform +-3.1e-5 px error, ~1.8e-5 px per coordinate, ~2.5e-5 px Euclidean RMS (measured 1.0e-5).
constexpr double kFloatPixelsRmsPx = 5e-5;
constexpr double kExactDeg = 1e-5;
constexpr double kExactM = 1e-6;
constexpr double kExactRel = 1e-5;

SyntheticRigFrames Frames(const CameraRig& rig, int num_frames, uint64_t seed, double sigma_px) {
  RigFramesOptions o;
  o.num_frames = num_frames;
  o.pixel_sigma_px = sigma_px;
  Rng rng(seed);
  return MakeRigFrames(rig, o, &rng);
}

// Per-camera intrinsics as a single-camera calibration leaves them: a little off.
CameraRig RoughStart(CameraRig rig) {
  for (RigCamera& camera : rig.cameras) {
    camera.intrinsics.fku_px *= 1.01, camera.intrinsics.fkv_px *= 0.99;
    camera.intrinsics.u0_px += 2, camera.intrinsics.k1 += 0.01;
    camera.cam_from_rig = Rigid3();
  }
  return rig;
}

void ExpectNearRig(const CameraRig& got, const CameraRig& truth) {
  EXPECT_LT(RotationAngleDeg(got.cameras[1].cam_from_rig.rotation,
                             truth.cameras[1].cam_from_rig.rotation),
            kExactDeg);
  EXPECT_LT(
      (got.cameras[1].cam_from_rig.translation - truth.cameras[1].cam_from_rig.translation).norm(),
      kExactM);
  for (int c = 0; c < 2; ++c) {
    const IntrinsicsArray a = got.cameras[c].intrinsics.Params();
    const IntrinsicsArray b = truth.cameras[c].intrinsics.Params();
    for (int i = 0; i < 10; ++i) {
      EXPECT_NEAR(a[i], b[i], kExactRel * std::max(1.0, std::abs(b[i]))) << c << " " << i;
    }
  }
}

TEST(StereoOpenCv, RadTanRigFromExactFrames) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 16, 41, 0.0);
  const StereoOpenCvResult result = CalibrateStereoOpenCv(s.frames, RoughStart(truth), {});
  ASSERT_TRUE(result.IsUsable()) << result.message;
  EXPECT_LT(result.rms_reproj_px, kFloatPixelsRmsPx);
  ExpectNearRig(result.rig, truth);
  // Frames a single camera saw are skipped.
  int both = 0;
  for (const RigFrame& frame : s.frames) {
    both += !frame.views_by_camera[0].points.empty() && !frame.views_by_camera[1].points.empty();
  }
  EXPECT_EQ(static_cast<int>(result.used_frames.size()), both);
}

TEST(StereoOpenCv, FixedIntrinsicsGiveThePoseOnly) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 10, 42, 0.0);
  CameraRig start = truth;
  start.cameras[1].cam_from_rig = Rigid3();
  StereoOpenCvOptions o;
  o.fix_intrinsics = true;
  const StereoOpenCvResult result = CalibrateStereoOpenCv(s.frames, start, o);
  ASSERT_TRUE(result.IsUsable()) << result.message;
  ExpectNearRig(result.rig, truth);
  EXPECT_EQ(result.rig.cameras[0].intrinsics, truth.cameras[0].intrinsics);
}

TEST(StereoOpenCv, EquidistantRigThroughCvFisheye) {
  CameraRig truth = ExampleStereoRig();
  for (RigCamera& camera : truth.cameras) {
    CameraIntrinsics k;
    k.family = LensFamily::kEquidistant;
    k.fku_px = camera.intrinsics.fku_px * 0.8, k.fkv_px = camera.intrinsics.fkv_px * 0.8;
    k.u0_px = camera.intrinsics.u0_px, k.v0_px = camera.intrinsics.v0_px;
    k.k1 = 0.02, k.k2 = -0.01, k.k3 = 0.004, k.k4 = -0.001;
    camera.intrinsics = k;
    camera.lens_model = LensModel::kPinholeEqui;
  }
  const SyntheticRigFrames s = Frames(truth, 16, 43, 0.0);
  StereoOpenCvOptions o;
  o.model = LensModel::kPinholeEqui;
  const StereoOpenCvResult result = CalibrateStereoOpenCv(s.frames, RoughStart(truth), o);
  ASSERT_TRUE(result.IsUsable()) << result.message;
  ExpectNearRig(result.rig, truth);
}

TEST(StereoOpenCv, RefusesOmnidirectionalModels) {
  StereoOpenCvOptions o;
  o.model = LensModel::kDoubleSphere;
  const StereoOpenCvResult result = CalibrateStereoOpenCv({}, ExampleStereoRig(), o);
  EXPECT_FALSE(result.IsUsable());
  EXPECT_NE(result.message.find("no double-sphere lens model"), std::string::npos)
      << result.message;
}

// The same corners (noisy, sigma 0.5 px) through OpenCV and RefineRig (the same model, skew
// fixed as OpenCV fixes it): both are the maximum-likelihood estimate, so they differ by the two
// solvers' stopping points and OpenCV's float pixels only, far inside RefineRig's reported std
// (measured: 4e-5 of it). The bar: a hundredth of it.
constexpr double kAgreementShareOfStd = 0.01;

TEST(StereoOpenCv, AgreesWithRefineRigWithinItsStd) {
  const CameraRig truth = ExampleStereoRig();
  const SyntheticRigFrames s = Frames(truth, 24, 44, 0.5);
  const CameraRig start = RoughStart(truth);
  const StereoOpenCvResult cv_result = CalibrateStereoOpenCv(s.frames, start, {});
  ASSERT_TRUE(cv_result.IsUsable()) << cv_result.message;
  // RefineRig on exactly the frames OpenCV used.
  std::vector<RigFrame> used;
  std::vector<Rigid3> poses;
  for (int f : cv_result.used_frames)
    used.push_back(s.frames[f]), poses.push_back(s.rig_from_board[f]);
  RigRefineOptions o;
  o.models = {LensModel::kPinholeRadTan4, LensModel::kPinholeRadTan4};
  CameraRig rig_start = start;
  rig_start.cameras[1].cam_from_rig = truth.cameras[1].cam_from_rig;
  const RigRefineResult ours = RefineRig(used, rig_start, poses, o);
  ASSERT_TRUE(ours.IsUsable()) << ours.message;
  const RigPoseUncertainty& u = ours.pose_uncertainty[1];
  const Eigen::Vector3d dr = cv_result.rig.RelativeRotationDeg(1) - ours.rig.RelativeRotationDeg(1);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(std::abs(dr[k]), kAgreementShareOfStd * u.rotation_std_deg[k]) << "axis " << k;
  }
  const double db_mm = 1000 * (cv_result.rig.BaselineM(1) - ours.rig.BaselineM(1));
  EXPECT_LT(std::abs(db_mm), kAgreementShareOfStd * u.baseline_std_mm);
  for (int c = 0; c < 2; ++c) {
    EXPECT_LT(std::abs(cv_result.rig.cameras[c].intrinsics.fku_px -
                       ours.rig.cameras[c].intrinsics.fku_px),
              kAgreementShareOfStd * ours.intrinsics_std[c][0]);
  }
  // OpenCV's RMS is the same per-corner Euclidean RMS over both cameras.
  EXPECT_NEAR(cv_result.rms_reproj_px, ours.rms_reproj_px, 1e-3 * ours.rms_reproj_px);
  std::printf(
      "rotation diff %.2e %.2e %.2e deg (std %.3f %.3f %.3f); baseline diff %.2e mm (std "
      "%.3f); rms %.5f vs %.5f\n",
      dr[0], dr[1], dr[2], u.rotation_std_deg[0], u.rotation_std_deg[1], u.rotation_std_deg[2],
      db_mm, u.baseline_std_mm, cv_result.rms_reproj_px, ours.rms_reproj_px);
}

}  // namespace
}  // namespace calibench
