// `calibench compare A B` and `calibrate --cross-validate` end to end through the executable, on
// Zhang's bundled points: two models of one camera agree, a file without uncertainty is judged by
// the other's alone, different image sizes compare over the common pixels, and bad files are
// refused naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/common/cli_run.h"

namespace calibench {
namespace {

std::string Temp(const std::string& name) { return ::testing::TempDir() + "/compare_cli/" + name; }

CliRun Calibench(const std::string& args) {
  std::filesystem::create_directories(Temp(""));
  return RunCli(CALIBENCH_BINARY, args);
}

const std::string kZhang = std::string(CALIBENCH_BUNDLED_DATA_DIR) + "/zhang";

TEST(CompareCli, TwoModelsOfOneCameraAgreeAndTheMapIsWritten) {
  const CliRun k2 =
      Calibench("calibrate --points " + kZhang + " --model pinhole-k2 --out " + Temp("k2.yaml"));
  ASSERT_EQ(k2.exit_code, 0) << k2.output;
  EXPECT_NE(k2.output.find("Projection uncertainty (rays at infinity"), std::string::npos)
      << k2.output;
  EXPECT_TRUE(std::filesystem::is_regular_file(Temp("k2.md")));
  const CliRun r4 = Calibench("calibrate --points " + kZhang + " --model pinhole-radtan4 --out " +
                              Temp("r4.yaml"));
  ASSERT_EQ(r4.exit_code, 0) << r4.output;
  const CliRun compare = Calibench("compare " + Temp("k2.yaml") + " " + Temp("r4.yaml") +
                                   " --out " + Temp("diff.png"));
  ASSERT_EQ(compare.exit_code, 0) << compare.output;
  EXPECT_NE(compare.output.find("Verdict: AGREE"), std::string::npos) << compare.output;
  EXPECT_TRUE(std::filesystem::is_regular_file(Temp("diff.png")));
}

TEST(CompareCli, AFileWithoutUncertaintyIsJudgedByTheOthersAlone) {
  ASSERT_EQ(Calibench("calibrate --points " + kZhang + " --out " + Temp("a.yaml")).exit_code, 0);
  ASSERT_EQ(Calibench("calibrate --points " + kZhang + " --out " + Temp("b.cameramodel")).exit_code,
            0);
  const CliRun compare = Calibench("compare " + Temp("a.yaml") + " " + Temp("b.cameramodel"));
  ASSERT_EQ(compare.exit_code, 0) << compare.output;
  EXPECT_NE(compare.output.find("without projection uncertainty"), std::string::npos)
      << compare.output;
  EXPECT_NE(compare.output.find("within a.yaml's uncertainty alone (b.cameramodel carries none)"),
            std::string::npos)
      << compare.output;
}

TEST(CompareCli, DifferentImageSizesAreComparedOverTheCommonPixels) {
  ASSERT_EQ(Calibench("calibrate --points " + kZhang + " --out " + Temp("full.yaml")).exit_code, 0);
  // The same camera declared for a 320 x 480 crop (the left half of the pixels).
  std::ifstream in(Temp("full.yaml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t width = text.find("image_width: 640");
  ASSERT_NE(width, std::string::npos);
  text.replace(width, 16, "image_width: 320");
  std::ofstream(Temp("half.yaml")) << text;
  const CliRun compare = Calibench("compare " + Temp("full.yaml") + " " + Temp("half.yaml"));
  ASSERT_EQ(compare.exit_code, 0) << compare.output;
  EXPECT_NE(compare.output.find("the image sizes differ"), std::string::npos) << compare.output;
  EXPECT_NE(compare.output.find("50 % of it common"), std::string::npos) << compare.output;
}

TEST(CompareCli, UnreadableFilesAreRefusedNamingThem) {
  std::filesystem::create_directories(Temp(""));
  std::ofstream(Temp("garbage.yaml")) << "this is: [not a camera\n";
  const CliRun garbage = Calibench("compare " + Temp("garbage.yaml") + " " + Temp("garbage.yaml"));
  EXPECT_EQ(garbage.exit_code, 2) << garbage.output;
  EXPECT_NE(garbage.output.find(Temp("garbage.yaml")), std::string::npos) << garbage.output;
  const CliRun missing = Calibench("compare " + Temp("none.yaml") + " " + Temp("none.yaml"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("none.yaml: no such file"), std::string::npos) << missing.output;
}

TEST(CalibrateCli, CrossValidateComparesTheTwoHalves) {
  // Zhang's five views: too few to split (3 per half): said, and the calibration still written.
  const CliRun run =
      Calibench("calibrate --points " + kZhang + " --cross-validate --out " + Temp("cv.yaml"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("cross-validation: not done: 5 views"), std::string::npos)
      << run.output;
}

}  // namespace
}  // namespace calibench
