// `calibench calibrate --points FILE --model unified|eucm|double-sphere|auto` end to end through
// the executable: a synthetic 160-degree fisheye written as an OpenCV calibration file (whole
// boards: the format has one pattern size), the intrinsics printed with their standard
// deviations, the camera file written and read back.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/camera_io.h"
#include "sim/synthetic.h"
#include "tests/common/cli_run.h"
#include "util/random.h"

namespace calibench {
namespace {

std::string Temp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

// The views as OpenCV's calib.dat (io/points_io.h): size, pattern, views, flags, object
// points per view, image points per view.
void WriteCalibDat(const std::string& path, const SyntheticBoardViews& data, int side, int rows,
                   int cols) {
  std::ofstream out(path);
  out.precision(17);
  out << side << " " << side << "\n" << cols << " " << rows << "\n" << data.views.size() << "\n0\n";
  for (const View& v : data.views) {
    for (const Eigen::Vector3d& p : v.points) out << p.x() << " " << p.y() << " 0\n";
  }
  for (const View& v : data.views) {
    for (const Eigen::Vector2d& p : v.pixels) out << p.x() << " " << p.y() << "\n";
  }
}

CliRun Calibench(const std::string& args) { return RunCli(CALIBENCH_BINARY, args); }

// Mutation caught: the CLI without --model auto (exit 2: "unknown lens model 'auto'").
TEST(CalibrateCli, WideModelsAndAutoEndToEnd) {
  CameraIntrinsics truth;
  truth.family = LensFamily::kEucm;
  truth.fku_px = 300, truth.fkv_px = 300.9, truth.u0_px = 515.3, truth.v0_px = 508.6;
  truth.alpha = 0.62, truth.beta = 1.05;
  Rng rng(5);
  WideBoardOptions o;
  o.num_views = 16;
  o.max_angle_deg = 80;
  o.min_visible_fraction = 1.0;
  o.pixel_sigma_px = 0.2;
  const SyntheticBoardViews data = MakeWideBoardViews(truth, o, &rng);
  ASSERT_EQ(data.views.size(), 16u);
  const std::string dat = Temp("eucm160.dat");
  WriteCalibDat(dat, data, 1024, o.rows, o.cols);
  for (const char* model : {"unified", "eucm", "double-sphere"}) {
    const std::string camera = Temp(std::string(model) + "-camchain.yaml");
    const CliRun run =
        Calibench("calibrate --points " + dat + " --model " + model + " --out " + camera);
    EXPECT_EQ(run.status, 0) << run.output;
    // Every free lens parameter printed with its std.
    for (const char* field : {std::string(model) == "eucm" ? "beta " : "xi ",
                              std::string(model) == "unified" ? "k1 " : "alpha "}) {
      const size_t at = run.output.find(std::string("\n") + field);
      ASSERT_NE(at, std::string::npos) << model << " " << field << "\n" << run.output;
      EXPECT_NE(run.output.find("+-", at), std::string::npos) << run.output;
    }
    EXPECT_NE(run.output.find("wide start"), std::string::npos) << run.output;
    CameraFile back;
    std::string why;
    ASSERT_TRUE(ReadCameraFile(camera, &back, &why)) << why;
    EXPECT_EQ(ToString(back.lens_model), std::string(model));
  }
  const CliRun run =
      Calibench("calibrate --points " + dat + " --model auto --out " + Temp("auto.yaml"));
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("rule: the fewest parameters among the models within noise"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("picked: "), std::string::npos) << run.output;
  std::cout << run.output;
  CameraFile picked;
  std::string why;
  ASSERT_TRUE(ReadCameraFile(Temp("auto.yaml"), &picked, &why)) << why;
  EXPECT_NE(picked.lens_model, LensModel::kPinholeK2);
  // mrcal cannot hold the wide families: refused with the reason, exit 3.
  const CliRun mrcal =
      Calibench("calibrate --points " + dat + " --model eucm --out " + Temp("eucm.cameramodel"));
  EXPECT_NE(mrcal.output.find("mrcal 2.2 has no eucm"), std::string::npos) << mrcal.output;
  EXPECT_EQ(WEXITSTATUS(mrcal.status), 3);
}

}  // namespace
}  // namespace calibench
