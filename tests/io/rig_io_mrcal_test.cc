// mrcal itself (Debian's python3-mrcal) reads the .cameramodel files of a rig (io/rig_io.h) and
// gets the extrinsics rt_cam_ref we wrote. Label python: skipped when mrcal is not installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/rig_io.h"

namespace calibench {
namespace {

// mrcal parses our 17-digit numbers into the same doubles and prints them with repr (exact):
// what it reads is what we wrote, up to the text round trip (none).
constexpr double kMrcalExtrinsicsTol = 1e-15;

std::string Temp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

TEST(RigFileMrcal, MrcalReadsOurExtrinsics) {
  if (std::system("/usr/bin/python3 -c 'import mrcal' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "mrcal's python module is not installed (Debian: python3-mrcal)";
  }
  RigFile rig;
  const Eigen::Vector3d rs[3] = {{0, 0, 0}, {0.0123, -0.0171, 0.0042}, {-0.03, 0.2, -0.01}};
  const Eigen::Vector3d ts[3] = {{0, 0, 0}, {-0.12, 0.0011, 0.0023}, {0.003, 0.0812, -0.0151}};
  for (int c = 0; c < 3; ++c) {
    RigCamera camera;
    camera.intrinsics.k1 = -0.25, camera.intrinsics.k2 = 0.07, camera.intrinsics.p1 = 1e-3;
    camera.intrinsics.fku_px = 800 + 10 * c;
    camera.lens_model = LensModel::kPinholeRadTan4;
    camera.image_width = 640, camera.image_height = 480;
    camera.cam_from_rig = {ExpSO3(rs[c]), ts[c]};
    rig.rig.cameras.push_back(camera);
  }
  const std::string base = Temp("mrcal_rig.cameramodel");
  std::string why;
  ASSERT_TRUE(WriteRigFile(base, CameraFormat::kMrcal, rig, &why)) << why;
  const std::vector<std::string> paths = MrcalRigPaths(base, 3);
  std::ofstream(Temp("mrcal_rig.py"))
      << "import sys, mrcal\n"
         "for p in sys.argv[1:]:\n"
         "    m = mrcal.cameramodel(p)\n"
         "    print(' '.join(repr(float(x)) for x in m.extrinsics_rt_fromref()),\n"
         "          m.intrinsics()[1][0])\n";
  const std::string command = "/usr/bin/python3 " + Temp("mrcal_rig.py") + " " + paths[0] + " " +
                              paths[1] + " " + paths[2] + " > " + Temp("mrcal_rig.txt") + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream out(Temp("mrcal_rig.txt"));
  for (int c = 0; c < 3; ++c) {
    std::string line;
    ASSERT_TRUE(std::getline(out, line)) << "camera " << c;
    std::istringstream fields(line);
    double rt[6], fx = 0;
    for (double& v : rt) fields >> v;
    fields >> fx;
    ASSERT_FALSE(fields.fail()) << line;
    const Rigid3& pose = rig.rig.cameras[c].cam_from_rig;
    const Eigen::Vector3d r = LogSO3(pose.rotation);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(rt[i], r(i), kMrcalExtrinsicsTol) << "camera " << c << ": " << line;
      EXPECT_NEAR(rt[3 + i], pose.translation(i), kMrcalExtrinsicsTol) << line;
    }
    EXPECT_EQ(fx, rig.rig.cameras[c].intrinsics.fku_px) << line;
  }
}

}  // namespace
}  // namespace calibench
