// detect --images (calib/detect_images.h) on rendered Kalibr AprilGrids written as 8-bit and
// as 16-bit PNGs: every tag found, corners at the exact projections, the CSV as documented.
#include "calib/detect_images.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "bench/app/corners_csv.h"
#include "bench/run/csv.h"
#include "calib/image_points.h"
#include "io/target_io.h"
#include "sim/render.h"
#include "sim/synthetic.h"
#include "tests/common/temp_files.h"

namespace calibench {
namespace {

// A clean 640 x 480 render read back through the photometric refinement: 0.013 px RMS measured
// (the edge fit: ~0.03 px); 0.05 px is the suite's bound for a clean render.
constexpr double kCornerRmsTolPx = 0.05;
// 16-bit -> 8-bit by percentiles re-quantises the gray levels (up to 0.5 level of 215): a second
// quantisation noise as large as the image's own, so the corners move by about the error that the
// clean render's quantisation leaves (0.013 px RMS): RMS shift <= 0.02 px, any one <= 0.05 px.
constexpr double kSixteenBitShiftRmsTolPx = 0.02;
constexpr double kSixteenBitShiftMaxTolPx = 0.05;

struct Rendered {
  AprilGrid grid;
  CameraIntrinsics camera{600, 600, 90, 319.5, 239.5};
  Rigid3 cam_from_board;
  GrayImage image;
};

Rendered RenderKalibrGrid() {
  Rendered r;
  BoardView view = SixByFiveTagGrid();  // sim/synthetic.h, with Kalibr's 2-bit border.
  view.grid.black_tag_border = 2;
  view.family = TagFamily::Create("tag36h11", 2, nullptr);
  r.grid = view.grid;
  view.cam_from_board = FacingBoardPose({0.2, -0.15, 0.3},
                                        {3 * r.grid.Pitch(), 2.5 * r.grid.Pitch(), 0}, {0, 0, 0.5});
  r.cam_from_board = view.cam_from_board;
  std::string why;
  EXPECT_TRUE(RenderFrame(r.camera, {view}, RenderOptions(), nullptr, &r.image, &why)) << why;
  return r;
}

CalibrationTarget TargetOf(const AprilGrid& grid) {
  CalibrationTarget t;
  t.type = CalibrationTarget::Type::kAprilGrid;
  t.grid = grid;
  return t;
}

TEST(DetectImages, EightAndSixteenBitPngsGiveTheExactCorners) {
  const Rendered r = RenderKalibrGrid();
  const std::string dir = FreshTempDir("/detect_images", "");
  std::filesystem::create_directories(dir);
  const cv::Mat eight(r.image.height, r.image.width, CV_8UC1,
                      const_cast<uint8_t*>(r.image.pixels.data()));
  cv::Mat sixteen;
  eight.convertTo(sixteen, CV_16U, 40.0, 3000.0);  // Levels 3800..12400 of 65535: a dim sensor.
  ASSERT_TRUE(cv::imwrite(dir + "/a_eight.png", eight));
  ASSERT_TRUE(cv::imwrite(dir + "/b_sixteen.png", sixteen));
  std::vector<ImageCorners> images;
  std::string why;
  ASSERT_TRUE(DetectImageCorners(dir, TargetOf(r.grid), &images, &why)) << why;
  ASSERT_EQ(images.size(), 2u);
  EXPECT_TRUE(images[0].note.empty());
  EXPECT_NE(images[1].note.find("16-bit"), std::string::npos) << images[1].note;
  const std::vector<Eigen::Vector3d> corners = r.grid.CornersInBoard();
  for (const ImageCorners& image : images) {
    EXPECT_EQ(image.tags, 30) << image.file;  // Every tag is in view.
    ASSERT_EQ(image.corners.size(), 120u) << image.file;
    double sum_sq = 0;
    for (const ImageCorners::Corner& c : image.corners) {
      Eigen::Vector2d truth;
      ASSERT_TRUE(
          ProjectPoint(r.camera, r.cam_from_board * corners[4 * c.tag_id + c.corner], &truth));
      sum_sq += (Eigen::Vector2d(c.u_px, c.v_px) - truth).squaredNorm();
    }
    const double rms = std::sqrt(sum_sq / image.corners.size());
    std::printf("%s: %d tags, corner RMS %.4f px vs exact projections\n", image.file.c_str(),
                image.tags, rms);
    EXPECT_LT(rms, kCornerRmsTolPx) << image.file;
  }
  double shift_sq = 0;
  for (size_t k = 0; k < images[0].corners.size(); ++k) {
    const ImageCorners::Corner &a = images[0].corners[k], &b = images[1].corners[k];
    EXPECT_EQ(a.tag_id, b.tag_id);
    EXPECT_EQ(a.corner, b.corner);
    const double shift = std::hypot(a.u_px - b.u_px, a.v_px - b.v_px);
    EXPECT_LT(shift, kSixteenBitShiftMaxTolPx);
    shift_sq += shift * shift;
    EXPECT_GT(a.crlb_px, 0.0);  // The photometric fit's floor, reported per corner.
    EXPECT_LT(a.crlb_px, 0.05);
  }
  EXPECT_LT(std::sqrt(shift_sq / images[0].corners.size()), kSixteenBitShiftRmsTolPx);

  // The CSV: a header, then one row per corner in image, tag, corner order.
  const std::string csv = ImageCornersCsv(images);
  std::istringstream in(csv);
  CsvReader reader(&in);
  std::vector<std::string> fields;
  ASSERT_TRUE(reader.Next(&fields, &why)) << why;
  EXPECT_EQ(fields,
            (std::vector<std::string>{"image", "tag_id", "corner", "u_px", "v_px", "crlb_px"}));
  int rows = 0;
  while (reader.Next(&fields, &why)) {
    ASSERT_EQ(fields.size(), 6u);
    const ImageCorners::Corner& c = images[rows / 120].corners[rows % 120];
    EXPECT_EQ(fields[0], images[rows / 120].file);
    EXPECT_EQ(std::stoi(fields[1]), c.tag_id);
    EXPECT_EQ(std::stoi(fields[2]), c.corner);
    EXPECT_NEAR(std::stod(fields[3]), c.u_px, 1e-6);
    ++rows;
  }
  EXPECT_EQ(rows, 240);
  EXPECT_EQ(images[0].corners[0].tag_id, 0);
  EXPECT_EQ(images[0].corners[1].corner, 1);
  const std::string report = FormatImageCorners(images, TargetOf(r.grid));
  EXPECT_NE(report.find("a_eight.png                     30 of 30 tags"), std::string::npos)
      << report;
  EXPECT_NE(report.find("2 images, 60 tags, 240 corners"), std::string::npos) << report;
}

// A checkerboard folder (the bundled opencv-left set, 9 x 6 inner corners): every image's
// corners are those calibrate --images uses (LoadImagePoints, the same detector), in row-major
// order with their board points; the CSV leaves tag_id empty and numbers the inner corners.
TEST(DetectImages, CheckerboardCornersAreCalibratesInRowMajorOrder) {
  const std::string dir = std::string(CALIBENCH_BUNDLED_DATA_DIR) + "/opencv-left";
  CalibrationTarget target;
  std::string why;
  ASSERT_TRUE(LoadTargetYaml(dir + "/checkerboard.yaml", &target, &why)) << why;
  std::vector<ImageCorners> images;
  ASSERT_TRUE(DetectImageCorners(dir, target, &images, &why)) << why;
  PointData data;
  ImageFolderReport report;
  std::vector<int> used;
  ASSERT_TRUE(LoadImagePoints(dir, target, &data, &report, &used, &why)) << why;
  ASSERT_EQ(images.size(), report.images.size());
  size_t view = 0;
  for (size_t i = 0; i < images.size(); ++i) {
    if (!report.images[i].used) {
      EXPECT_TRUE(images[i].corners.empty()) << images[i].file;
      continue;
    }
    ASSERT_EQ(images[i].corners.size(), data.views[view].pixels.size()) << images[i].file;
    for (size_t k = 0; k < images[i].corners.size(); ++k) {
      const ImageCorners::Corner& c = images[i].corners[k];
      EXPECT_EQ(c.tag_id, -1);
      EXPECT_EQ(c.corner, static_cast<int>(k));
      EXPECT_EQ(Eigen::Vector2d(c.u_px, c.v_px), data.views[view].pixels[k]);
      // Corner k is (c colSpacing, r rowSpacing) with k = r cols + c.
      const int col = static_cast<int>(k) % target.cols, row = static_cast<int>(k) / target.cols;
      EXPECT_EQ(data.views[view].points[k],
                Eigen::Vector3d(col * target.col_spacing_m, row * target.row_spacing_m, 0));
    }
    ++view;
  }
  EXPECT_EQ(view, data.views.size());
  EXPECT_GE(view, 10u);  // opencv-left: the pattern is found in every image.
  const std::string csv = ImageCornersCsv(images);
  EXPECT_NE(csv.find("\nleft01.jpg,,0,"), std::string::npos) << csv.substr(0, 200);
  EXPECT_NE(FormatImageCorners(images, target).find("54 of 54 corners"), std::string::npos);
}

TEST(DetectImages, BadFolderTargetAndImagesAreReported) {
  std::vector<ImageCorners> images;
  std::string why;
  const Rendered r = RenderKalibrGrid();
  EXPECT_FALSE(DetectImageCorners("/nonexistent_dir", TargetOf(r.grid), &images, &why));
  EXPECT_NE(why.find("/nonexistent_dir: cannot list the folder"), std::string::npos) << why;
  const std::string dir = FreshTempDir("/detect_images_bad", "");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/broken.png") << "not a png";
  ASSERT_TRUE(DetectImageCorners(dir, TargetOf(r.grid), &images, &why)) << why;
  ASSERT_EQ(images.size(), 1u);
  EXPECT_FALSE(images[0].readable);
  EXPECT_NE(FormatImageCorners(images, TargetOf(r.grid)).find("broken.png"), std::string::npos);
  EXPECT_NE(images[0].note.find("cannot be decoded"), std::string::npos) << images[0].note;
}

}  // namespace
}  // namespace calibench
