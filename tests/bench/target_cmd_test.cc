// calibench target (bench/app/target_cmd.h): the PNG read back by our own detectors gives the
// layout (every id, the corner pitch), the PDF's page is the physical size, the YAML re-loads.
#include "bench/app/target_cmd.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "calib/detect_images.h"
#include "calib/image_points.h"
#include "tests/common/temp_files.h"

namespace calibench {
namespace {

// A print at `dpi` seen straight on: a corner's pixel is known exactly from the layout (the
// raster is exact area coverage). Measured on this unblurred PNG: the edge fit alone is within
// 0.001 px of it; the saddle refinement that Kalibr's corner squares get (frame_detector.h) is
// biased on one-pixel-wide edges, by +0.02..+0.07 px per corner (RMS 0.087 px, worst 0.118 px;
// 0.044 px RMS once blurred by sigma = 1 px, as a camera would). Tolerances: 0.15 px per corner,
// 0.1 px RMS; the pitch, a difference over three tags, within 0.05 px (1/6000 of it).
constexpr double kCornerTolPx = 0.15, kCornerRmsTolPx = 0.1, kPitchTolPx = 0.05;
// MediaBox numbers are written to 1e-4 pt.
constexpr double kMediaBoxTolPt = 1e-3;

std::string WriteBoard(const TargetArgs& args) {
  std::filesystem::create_directories(std::filesystem::path(args.out_path).parent_path());
  EXPECT_EQ(WriteTarget(args), 0);
  return std::filesystem::path(args.out_path).replace_extension().string();
}

// The page (m) from the PDF's MediaBox.
void MediaBox(const std::string& pdf, double* w_m, double* h_m) {
  std::smatch m;
  ASSERT_TRUE(std::regex_search(pdf, m, std::regex(R"(/MediaBox \[0 0 ([0-9.]+) ([0-9.]+)\])")));
  *w_m = std::stod(m[1]) * 0.0254 / 72;
  *h_m = std::stod(m[2]) * 0.0254 / 72;
}

TEST(Target, AprilGridPrintIsDetectedWithItsLayout) {
  TargetArgs args;
  args.rows = 3;
  args.cols = 4;
  args.size_m = 0.03;
  args.spacing = 0.3;
  args.border_bits = 2;
  args.first_id = 5;
  args.margin_m = 0.01;
  args.dpi = 200;
  const std::string dir = FreshTempDir("/target_aprilgrid", "");
  args.out_path = dir + "/board.pdf";
  const std::string stem = WriteBoard(args);

  // The YAML describes the board; the detector reads the PNG with it.
  CalibrationTarget target;
  std::string why;
  ASSERT_TRUE(LoadTargetYaml(stem + ".yaml", &target, &why)) << why;
  EXPECT_EQ(target.grid.tag_rows, 3);
  EXPECT_EQ(target.grid.tag_cols, 4);
  EXPECT_EQ(target.grid.tag_size_m, 0.03);
  EXPECT_EQ(target.grid.tag_spacing, 0.3);
  EXPECT_EQ(target.grid.black_tag_border, 2);
  EXPECT_EQ(target.grid.first_id, 5);
  EXPECT_TRUE(target.grid.corner_squares);
  std::filesystem::remove(stem + ".pdf");  // Only the PNG is an image.
  std::vector<ImageCorners> images;
  ASSERT_TRUE(DetectImageCorners(dir, target, &images, &why)) << why;
  ASSERT_EQ(images.size(), 1u);
  EXPECT_EQ(images[0].tags, 12);
  EXPECT_EQ(images[0].unknown_tags, 0);
  ASSERT_EQ(images[0].corners.size(), 48u);

  // Corner k of tag (r, c) at board (c p + dx_k s, r p + dy_k s); the page's origin is one gap
  // plus the margin from the page's bottom-left; v counts from the top.
  TargetLayout layout;
  ASSERT_TRUE(MakeTargetLayout(args, &layout, &why)) << why;
  const double px_per_m = args.dpi / 0.0254, s = args.size_m, p = s * (1 + args.spacing);
  EXPECT_NEAR(layout.origin_x_m, args.margin_m + args.spacing * s, 1e-12);
  double worst = 0, sum_sq = 0;
  for (const ImageCorners::Corner& c : images[0].corners) {
    const int index = c.tag_id - 5, r = index / 4, col = index % 4;
    const double x = layout.origin_x_m + col * p + (c.corner == 1 || c.corner == 2 ? s : 0);
    const double y = layout.origin_y_m + r * p + (c.corner >= 2 ? s : 0);
    const double u = x * px_per_m - 0.5, v = (layout.page_h_m - y) * px_per_m - 0.5;
    worst = std::max(worst, std::hypot(c.u_px - u, c.v_px - v));
    sum_sq += std::pow(c.u_px - u, 2) + std::pow(c.v_px - v, 2);
  }
  const double rms = std::sqrt(sum_sq / images[0].corners.size());
  // The pitch in pixels, p dpi / 0.0254: corner 0 of tag 5 (bottom-left) to that of tag 8, three
  // tags to the right (the corners of tag i are entries 4 (i - 5) ..).
  const ImageCorners::Corner &a = images[0].corners[0], &b = images[0].corners[12];
  ASSERT_EQ(b.tag_id, 8);
  const double pitch = (b.u_px - a.u_px) / 3;
  std::printf(
      "aprilgrid print: 12 of 12 tags, corner RMS %.4f px, worst %.4f px, pitch %.4f px "
      "(%.4f)\n",
      rms, worst, pitch, p * px_per_m);
  EXPECT_LT(worst, kCornerTolPx);
  EXPECT_LT(rms, kCornerRmsTolPx);
  EXPECT_NEAR(pitch, p * px_per_m, kPitchTolPx);

  double w_m = 0, h_m = 0;
  const std::string pdf = TargetPdf(layout);
  MediaBox(pdf, &w_m, &h_m);
  const double pattern_w = 3 * p + s + 2 * args.spacing * s,
               pattern_h = 2 * p + s + 2 * args.spacing * s;
  EXPECT_NEAR(w_m * 72 / 0.0254, (pattern_w + 2 * args.margin_m) * 72 / 0.0254, kMediaBoxTolPt);
  EXPECT_NEAR(h_m * 72 / 0.0254, (pattern_h + 2 * args.margin_m) * 72 / 0.0254, kMediaBoxTolPt);
  EXPECT_EQ(pdf.rfind("%PDF-1.4\n", 0), 0u);
  EXPECT_NE(pdf.find("re f\n"), std::string::npos);
  // The xref offset points at the xref table.
  const size_t startxref = pdf.rfind("startxref\n");
  ASSERT_NE(startxref, std::string::npos);
  EXPECT_EQ(pdf.compare(std::stoul(pdf.substr(startxref + 10)), 4, "xref"), 0);
}

TEST(Target, CheckerboardPrintIsDetectedWithItsPitch) {
  TargetArgs args;
  args.type = "checkerboard";
  args.rows = 5;
  args.cols = 7;
  args.size_m = 0.02;
  args.dpi = 150;
  const std::string dir = FreshTempDir("/target_checkerboard", "");
  args.out_path = dir + "/board.pdf";
  const std::string stem = WriteBoard(args);
  CalibrationTarget target;
  std::string why;
  ASSERT_TRUE(LoadTargetYaml(stem + ".yaml", &target, &why)) << why;
  EXPECT_EQ(target.type, CalibrationTarget::Type::kCheckerboard);
  EXPECT_EQ(target.rows, 5);
  EXPECT_EQ(target.cols, 7);
  EXPECT_EQ(target.row_spacing_m, 0.02);
  std::filesystem::remove(stem + ".pdf");
  PointData data;
  ImageFolderReport report;
  std::vector<int> used;
  ASSERT_TRUE(LoadImagePoints(dir, target, &data, &report, &used, &why)) << why;
  ASSERT_EQ(data.views.size(), 1u);
  const View& view = data.views[0];
  ASSERT_EQ(view.pixels.size(), 35u);
  const double pitch_px = args.size_m * args.dpi / 0.0254;
  // Neighbours along a row and along a column (corner (r, c) is point r * 7 + c).
  double worst = 0;
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c + 1 < 7; ++c) {
      worst = std::max(
          worst, std::abs((view.pixels[r * 7 + c + 1] - view.pixels[r * 7 + c]).norm() - pitch_px));
    }
  }
  for (int r = 0; r + 1 < 5; ++r) {
    worst = std::max(worst,
                     std::abs((view.pixels[(r + 1) * 7] - view.pixels[r * 7]).norm() - pitch_px));
  }
  std::printf("checkerboard print: 35 corners, pitch %.4f px, worst deviation %.4f px\n", pitch_px,
              worst);
  EXPECT_LT(worst, 2 * kPitchTolPx);  // Two corners' errors (the chessboard's cornerSubPix).
  TargetLayout layout;
  ASSERT_TRUE(MakeTargetLayout(args, &layout, &why));
  double w_m = 0, h_m = 0;
  MediaBox(TargetPdf(layout), &w_m, &h_m);
  EXPECT_NEAR(w_m * 72 / 0.0254, (8 * 0.02 + 2 * args.margin_m) * 72 / 0.0254, kMediaBoxTolPt);
  EXPECT_NEAR(h_m * 72 / 0.0254, (6 * 0.02 + 2 * args.margin_m) * 72 / 0.0254, kMediaBoxTolPt);
}

TEST(Target, BadArgumentsAreRefused) {
  TargetLayout layout;
  std::string why;
  TargetArgs args;
  args.border_bits = 3;
  EXPECT_FALSE(MakeTargetLayout(args, &layout, &why));
  EXPECT_NE(why.find("--border"), std::string::npos) << why;
  args = TargetArgs();
  args.first_id = 580;  // tag36h11 has 587 codes; 36 tags need ids up to 615.
  EXPECT_FALSE(MakeTargetLayout(args, &layout, &why));
  EXPECT_NE(why.find("587 codes"), std::string::npos) << why;
  args = TargetArgs();
  args.type = "checkerboard", args.rows = 10000, args.cols = 100;  // 1 010 101 squares.
  EXPECT_FALSE(MakeTargetLayout(args, &layout, &why));
  EXPECT_NE(why.find("--rows x --cols: at most 1000000 squares"), std::string::npos) << why;
  args.rows = 9800, args.size_m = 0.001;  // 989 901 squares on 9.8 x 0.1 m: accepted.
  EXPECT_TRUE(MakeTargetLayout(args, &layout, &why)) << why;
  args = TargetArgs();
  args.out_path = "board.png";  // The PNG would overwrite the PDF.
  EXPECT_FALSE(MakeTargetLayout(args, &layout, &why));
  EXPECT_NE(why.find("--out must name a .pdf file"), std::string::npos) << why;
  args = TargetArgs();
  args.size_m = -1;
  EXPECT_FALSE(MakeTargetLayout(args, &layout, &why));
  EXPECT_NE(why.find("--size"), std::string::npos) << why;
}

}  // namespace
}  // namespace calibench
