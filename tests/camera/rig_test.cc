#include "camera/rig.h"

#include <gtest/gtest.h>

#include "sim/example_rigs.h"

namespace calibench {
namespace {

TEST(CameraRig, StereoRigPassesAndReadsItsPose) {
  const CameraRig rig = ExampleStereoRig();
  std::string why;
  EXPECT_TRUE(rig.Check(&why)) << why;
  // cam1's centre sits at (0.12, 0.002, -0.001) m (sim/example_rigs.h): the baseline is its length.
  EXPECT_NEAR(rig.BaselineM(1), Eigen::Vector3d(0.12, 0.002, -0.001).norm(), 1e-12);
  EXPECT_LT((rig.CentreInRig(1) - Eigen::Vector3d(0.12, 0.002, -0.001)).norm(), 1e-12);
  // The example gives cam_from_rig's rotation vector (0.3, -0.5, 0.2) deg.
  EXPECT_LT((rig.RelativeRotationDeg(1) - Eigen::Vector3d(0.3, -0.5, 0.2)).norm(), 1e-10);
  EXPECT_LT((rig.CamFromCam(1, 0).translation - rig.cameras[1].cam_from_rig.translation).norm(),
            1e-15);
}

TEST(CameraRig, CheckNamesTheCameraAndTheField) {
  std::string why;
  CameraRig rig = ExampleStereoRig();
  rig.cameras[0].cam_from_rig.translation.x() = 0.01;
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("cam0: cam_from_rig"), std::string::npos) << why;
  EXPECT_NE(why.find("identity"), std::string::npos) << why;

  rig = ExampleStereoRig();
  rig.cameras[1].cam_from_rig.rotation.col(0) *= -1;  // A reflection.
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("cam1: cam_from_rig"), std::string::npos) << why;
  EXPECT_NE(why.find("improper"), std::string::npos) << why;

  rig = ExampleStereoRig();
  rig.cameras[1].cam_from_rig.translation.setZero();
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("baseline 0"), std::string::npos) << why;

  rig = ExampleStereoRig();
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
