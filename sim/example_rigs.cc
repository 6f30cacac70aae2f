#include "sim/example_rigs.h"

namespace calibench {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

// cam_from_rig of a camera whose centre is at `centre_in_rig`, turned by `rotation_deg` (rotation
// vector of cam_from_rig's rotation, camera/rig.h).
Rigid3 CamFromRig(const Eigen::Vector3d& rotation_deg, const Eigen::Vector3d& centre_in_rig) {
  const Eigen::Matrix3d r = ExpSO3(rotation_deg * kDegToRad);
  return {r, -(r * centre_in_rig)};
}

RigCamera RadTanCamera(const std::string& name, double f_px, double k1, double u0_px,
                       double v0_px) {
  RigCamera camera;
  camera.name = name;
  camera.intrinsics = {f_px, f_px * 1.002, 90.0, u0_px, v0_px};
  camera.intrinsics.k1 = k1;
  camera.intrinsics.k2 = 0.05;
  camera.intrinsics.p1 = 4e-4;
  camera.intrinsics.p2 = -3e-4;
  camera.lens_model = LensModel::kPinholeRadTan4;
  camera.image_width = 640;
  camera.image_height = 480;
  return camera;
}

}  // namespace

CameraRig ExampleStereoRig() {
  CameraRig rig;
  rig.cameras.push_back(RadTanCamera("cam0", 500.0, -0.20, 322.0, 238.0));
  rig.cameras.push_back(RadTanCamera("cam1", 505.0, -0.22, 317.0, 243.0));
  rig.cameras[1].cam_from_rig = CamFromRig({0.3, -0.5, 0.2}, {0.12, 0.002, -0.001});
  return rig;
}

CameraRig ExampleMixedThreeCameraRig() {
  CameraRig rig;
  rig.cameras.push_back(RadTanCamera("cam0", 500.0, -0.20, 322.0, 238.0));
  RigCamera wide;
  wide.name = "cam1";
  wide.intrinsics.family = LensFamily::kDoubleSphere;
  wide.intrinsics.fku_px = 190.0;
  wide.intrinsics.fkv_px = 190.5;
  wide.intrinsics.u0_px = 321.0;
  wide.intrinsics.v0_px = 241.0;
  wide.intrinsics.xi = -0.2;
  wide.intrinsics.alpha = 0.6;
  wide.lens_model = LensModel::kDoubleSphere;
  wide.image_width = 640;
  wide.image_height = 480;
  wide.cam_from_rig = CamFromRig({0.0, -45.0, 0.0}, {0.1, 0.0, 0.0});
  rig.cameras.push_back(wide);
  rig.cameras.push_back(RadTanCamera("cam2", 495.0, -0.18, 318.0, 236.0));
  rig.cameras[2].cam_from_rig = CamFromRig({0.0, -90.0, 0.0}, {0.2, 0.0, 0.0});
  return rig;
}

}  // namespace calibench
