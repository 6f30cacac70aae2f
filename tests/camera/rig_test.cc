#include "camera/rig.h"

#include <gtest/gtest.h>

#include "../common/synthetic_rigs.h"

namespace calibench {
namespace {

TEST(CameraRig, StereoRigPassesAndReadsItsPose) {
  const CameraRig rig = StereoRig();
  std::string why;
  EXPECT_TRUE(rig.Check(&why)) << why;
  // The right camera's centre sits 0.12 m along x (synthetic_rigs.h): the baseline is its length.
  EXPECT_NEAR(rig.BaselineM(1), Eigen::Vector3d(0.12, 0.002, -0.001).norm(), 1e-12);
  EXPECT_LT((rig.CentreInRig(1) - Eigen::Vector3d(0.12, 0.002, -0.001)).norm(), 1e-12);
  // rig_from_cam = Exp(r0) makes cam_from_rig's rotation vector -r0.
  EXPECT_LT((rig.RelativeRotationDeg(1) + Eigen::Vector3d(0.3, 0.8, 0.4)).norm(), 1e-10);
  EXPECT_LT((rig.CamFromCam(1, 0).translation - rig.cameras[1].cam_from_rig.translation).norm(),
            1e-15);
}

TEST(CameraRig, CheckNamesTheCameraAndTheField) {
  std::string why;
  CameraRig rig = StereoRig();
  rig.cameras[0].cam_from_rig.translation.x() = 0.01;
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("left: cam_from_rig"), std::string::npos) << why;
  EXPECT_NE(why.find("identity"), std::string::npos) << why;

  rig = StereoRig();
  rig.cameras[1].cam_from_rig.rotation.col(0) *= -1;  // A reflection.
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("right: cam_from_rig"), std::string::npos) << why;
  EXPECT_NE(why.find("improper"), std::string::npos) << why;

  rig = StereoRig();
  rig.cameras[1].cam_from_rig.translation.setZero();
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("baseline 0"), std::string::npos) << why;

  rig = StereoRig();
  rig.cameras[1].name.clear();
  rig.cameras[1].lens_model = LensModel::kDoubleSphere;
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("camera 1: lens_model"), std::string::npos) << why;

  rig.cameras.resize(1);
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("at least 2 cameras"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
