// Pairing the images of a rig's cameras (calib/rig_images.h) on empty files named like real data
// sets: OpenCV's stereo sample (left01..left14 without 10), globs, numbers without leading zeros,
// names without numbers, unpaired images and the errors.
#include "calib/rig_images.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace calibench {
namespace {

namespace fs = std::filesystem;

// A fresh folder under the test's temporary directory with empty files of these names.
std::string Folder(const std::string& name, const std::vector<std::string>& files) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("rig_images_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const std::string& f : files) std::ofstream(dir / f).put('\0');
  return dir.string();
}

std::vector<std::string> Numbered(const std::string& prefix, const std::string& ext,
                                  const std::vector<int>& numbers, int width = 2) {
  std::vector<std::string> names;
  for (int n : numbers) {
    std::string digits = std::to_string(n);
    while (static_cast<int>(digits.size()) < width) digits = "0" + digits;
    names.push_back(prefix + digits + ext);
  }
  return names;
}

// OpenCV's stereo sample data (../shared/data/opencv-stereo): left01..left14 and right01..right14
// without 10, in one folder: two globs.
TEST(RigImages, OpenCvStereoSampleNames) {
  const std::vector<int> numbers = {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14};
  std::vector<std::string> files = Numbered("left", ".jpg", numbers);
  for (const std::string& f : Numbered("right", ".jpg", numbers)) files.push_back(f);
  files.push_back("stereo_calib.xml");
  files.push_back("SOURCE.md");
  const std::string dir = Folder("opencv", files);
  const std::vector<std::string> sources = {dir + "/left*.jpg", dir + "/right*.jpg"};
  const RigImageSummary summary = PairRigImages(sources);
  ASSERT_TRUE(summary.ok) << summary.error;
  EXPECT_TRUE(summary.keyed_by_number);
  EXPECT_EQ(summary.images_per_source, (std::vector<int>{13, 13}));
  ASSERT_EQ(summary.frames.size(), 13u);
  EXPECT_TRUE(summary.unpaired.empty());
  EXPECT_EQ(summary.frames[0].key, "1");
  EXPECT_EQ(summary.frames[9].key, "11");  // Numbers in order, 10 missing.
  EXPECT_EQ(summary.frames[12].key, "14");
  for (const RigImageFrame& frame : summary.frames) {
    ASSERT_EQ(frame.path_by_camera.size(), 2u);
    const std::string left = fs::path(frame.path_by_camera[0]).filename().string();
    const std::string right = fs::path(frame.path_by_camera[1]).filename().string();
    EXPECT_EQ("right" + left.substr(4), right);
  }
  EXPECT_NE(summary.Report(sources).find("13 frames paired by the number in the names"),
            std::string::npos)
      << summary.Report(sources);
}

// Folders as sources; numbers pair by value (7 with 007), unpaired images are listed with their
// source, a key shared by two of three cameras is a frame.
TEST(RigImages, FoldersNumbersByValueAndUnpaired) {
  const std::string a = Folder("a", Numbered("cam0_", ".png", {1, 2, 3, 7, 20}, 1));
  const std::string b = Folder("b", Numbered("frame-", "-cam1.PNG", {2, 3, 7, 20, 21}, 3));
  const std::string c = Folder("c", Numbered("img", ".tif", {3, 7, 30}, 4));
  const RigImageSummary summary = PairRigImages({a, b, c});
  ASSERT_TRUE(summary.ok) << summary.error;
  EXPECT_TRUE(summary.keyed_by_number);
  ASSERT_EQ(summary.frames.size(), 4u);  // 2, 3, 7, 20.
  EXPECT_EQ(summary.frames[0].key, "2");
  EXPECT_TRUE(summary.frames[0].path_by_camera[2].empty());
  EXPECT_EQ(fs::path(summary.frames[1].path_by_camera[2]).filename(), "img0003.tif");
  EXPECT_EQ(fs::path(summary.frames[2].path_by_camera[1]).filename(), "frame-007-cam1.PNG");
  EXPECT_EQ(summary.frames[3].key, "20");
  ASSERT_EQ(summary.unpaired.size(), 3u);  // cam0_1, frame-021, img0030.
  EXPECT_EQ(summary.unpaired[0].source, 0);
  EXPECT_EQ(fs::path(summary.unpaired[0].path).filename(), "cam0_1.png");
  EXPECT_EQ(summary.unpaired[1].source, 1);
  EXPECT_EQ(summary.unpaired[2].source, 2);
  EXPECT_NE(summary.Report({a, b, c}).find("unpaired (camera 2):"), std::string::npos);

  // Every camera required: only 3 and 7 remain frames.
  RigImageOptions options;
  options.min_cameras_per_frame = 3;
  const RigImageSummary all = PairRigImages({a, b, c}, options);
  ASSERT_TRUE(all.ok) << all.error;
  ASSERT_EQ(all.frames.size(), 2u);
  EXPECT_EQ(all.frames[0].key, "3");
  EXPECT_EQ(all.unpaired.size(), 13u - 6u);
}

// A common prefix/suffix that ends inside a number is not cut there: left10, left20 .. pair with
// right10, right25 by 10 (not by "1").
TEST(RigImages, PrefixNeverSplitsANumber) {
  const std::string l = Folder("l", {"left10.png", "left20.png"});
  const std::string r = Folder("r", {"right10.png", "right25.png"});
  const RigImageSummary summary = PairRigImages({l, r});
  ASSERT_TRUE(summary.ok) << summary.error;
  ASSERT_EQ(summary.frames.size(), 1u);
  EXPECT_EQ(summary.frames[0].key, "10");
  EXPECT_EQ(summary.unpaired.size(), 2u);
}

// Names without numbers pair by what is left after the common prefix and suffix.
TEST(RigImages, NamesWithoutNumbers) {
  const std::string l = Folder("nl", {"left_a.jpg", "left_b.jpg", "left_c.jpg"});
  const std::string r = Folder("nr", {"a_right.jpg", "b_right.jpg", "x_right.jpg"});
  const RigImageSummary summary = PairRigImages({l, r});
  ASSERT_TRUE(summary.ok) << summary.error;
  EXPECT_FALSE(summary.keyed_by_number);
  ASSERT_EQ(summary.frames.size(), 2u);
  EXPECT_EQ(summary.frames[0].key, "a");
  EXPECT_EQ(summary.frames[1].key, "b");
  ASSERT_EQ(summary.unpaired.size(), 2u);  // left_c, x_right.
}

// A stray image without a number among numbered ones is unpaired; the others still pair by
// number. A glob without a folder reads the working directory.
TEST(RigImages, StrayUnnumberedImageAndBareGlob) {
  std::vector<std::string> left = Numbered("left", ".png", {1, 2, 3, 4, 5});
  left.push_back("left_test.png");
  const std::string l = Folder("sl", left);
  const std::string r = Folder("sr", Numbered("right", ".png", {1, 2, 3, 4, 5}, 1));
  const RigImageSummary summary = PairRigImages({l, r});
  ASSERT_TRUE(summary.ok) << summary.error;
  EXPECT_TRUE(summary.keyed_by_number);
  EXPECT_EQ(summary.frames.size(), 5u);
  ASSERT_EQ(summary.unpaired.size(), 1u);
  EXPECT_EQ(fs::path(summary.unpaired[0].path).filename(), "left_test.png");

  const fs::path cwd = fs::current_path();
  fs::current_path(l);
  std::vector<std::string> files;
  std::string why;
  EXPECT_TRUE(ListSourceImages("left0*.png", &files, &why)) << why;
  fs::current_path(cwd);
  ASSERT_EQ(files.size(), 5u);
  EXPECT_EQ(fs::path(files[0]).parent_path(), ".");  // A folder a caller can list and read.
}

TEST(RigImages, ErrorsNameTheSource) {
  const std::string l = Folder("el", {"left01.png", "left02.png"});
  const std::string r = Folder("er", {"right01.png", "right1.png", "right02.png"});
  const std::string empty = Folder("ee", {"notes.txt"});
  const std::string far = Folder("ef", {"x50.png", "x51.png"});

  RigImageSummary s = PairRigImages({l, empty});
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("camera 1: " + empty + ": no images"), std::string::npos) << s.error;

  s = PairRigImages({l, l + "/none*.png"});
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("camera 1: " + l + "/none*.png: matches no image"), std::string::npos)
      << s.error;

  s = PairRigImages({l, r});
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("camera 1: " + r + ": "), std::string::npos) << s.error;
  EXPECT_NE(s.error.find("have the same key '1'"), std::string::npos) << s.error;

  s = PairRigImages({l, far});
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("no number is shared by 2 sources"), std::string::npos) << s.error;
  EXPECT_NE(s.error.find(far), std::string::npos) << s.error;

  s = PairRigImages({l});
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("at least 2 sources"), std::string::npos) << s.error;

  RigImageOptions options;
  options.min_cameras_per_frame = 1;
  std::string why;
  EXPECT_FALSE(options.Check(&why));
  EXPECT_FALSE(PairRigImages({l, far}, options).ok);
}

}  // namespace
}  // namespace calibench
