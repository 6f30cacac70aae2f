// The synthetic rigs of the rig tests and benchmarks (batch/rig_refine.h, sim/rig_frames.h):
//   StereoRig():   two pinhole-radtan4 cameras 0.12 m apart, camera 1 turned by ~1 degree
//                  (EuRoC-like: 0.11 m, 0.8 deg);
//   MixedTriRig(): pinhole-radtan4, double-sphere, pinhole-radtan4 in a row; camera 2 looks 75
//                  degrees to the right of camera 0 (their fields never meet), the wide double
//                  sphere (TUM VI-like) between them sees both: camera 2 is linked through it.
#pragma once

#include <Eigen/Core>

#include "camera/rig.h"

namespace calibench {

// cam_from_rig of a camera turned by `rotation_vector_rad` (rig_from_cam = Exp of it) whose
// centre is `centre_in_rig`.
inline Rigid3 CamFromRigAt(const Eigen::Vector3d& rotation_vector_rad,
                           const Eigen::Vector3d& centre_in_rig) {
  const Eigen::Matrix3d rig_from_cam = ExpSO3(rotation_vector_rad);
  return {rig_from_cam.transpose(), -(rig_from_cam.transpose() * centre_in_rig)};
}

inline RigCamera RadTanCamera(const std::string& name, double fku, double u0, double k1) {
  RigCamera camera;
  camera.name = name;
  camera.intrinsics = CameraIntrinsics{fku, fku * 0.995, 90.0, u0, 241.0, k1, 0.06, 2e-4, -3e-4};
  camera.lens_model = LensModel::kPinholeRadTan4;
  camera.image_width = 640;
  camera.image_height = 480;
  return camera;
}

inline CameraRig StereoRig() {
  CameraRig rig;
  rig.cameras = {RadTanCamera("left", 520.0, 322.0, -0.21),
                 RadTanCamera("right", 515.0, 318.0, -0.19)};
  constexpr double kDeg = M_PI / 180.0;
  rig.cameras[1].cam_from_rig =
      CamFromRigAt(Eigen::Vector3d(0.3, 0.8, 0.4) * kDeg, Eigen::Vector3d(0.12, 0.002, -0.001));
  return rig;
}

inline CameraRig MixedTriRig() {
  CameraRig rig;
  RigCamera wide;
  wide.name = "wide";
  wide.intrinsics.family = LensFamily::kDoubleSphere;
  wide.intrinsics.fku_px = 190.0, wide.intrinsics.fkv_px = 189.0;
  wide.intrinsics.u0_px = 255.0, wide.intrinsics.v0_px = 257.0;
  wide.intrinsics.xi = -0.18, wide.intrinsics.alpha = 0.59;
  wide.lens_model = LensModel::kDoubleSphere;
  wide.image_width = 512, wide.image_height = 512;
  rig.cameras = {RadTanCamera("front", 520.0, 322.0, -0.21), wide,
                 RadTanCamera("side", 515.0, 318.0, -0.19)};
  constexpr double kDeg = M_PI / 180.0;
  rig.cameras[1].cam_from_rig =
      CamFromRigAt(Eigen::Vector3d(0.5, 37.0, 0.3) * kDeg, Eigen::Vector3d(0.10, 0.0, 0.0));
  rig.cameras[2].cam_from_rig =
      CamFromRigAt(Eigen::Vector3d(-0.4, 75.0, 0.6) * kDeg, Eigen::Vector3d(0.20, 0.01, 0.05));
  return rig;
}

}  // namespace calibench
