// Figures of a calibration (calib/calibration_pictures.h): the worst region and the coverage count
// on hand-made data, the PNGs' sizes read back, the heatmap's colours against its colour bar, and
// the failures (unwritable path, empty map) with a why that names the file.
#include "calib/calibration_pictures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

namespace calibench {
namespace {

namespace fs = std::filesystem;

// Means of a few exact small numbers: exact up to rounding.
constexpr double kExactTol = 1e-12;
// One figure pixel: the plot's height is the image frame's height scaled and rounded.
constexpr double kRoundingPx = 1.0;
// Colour match between the heatmap and its colour bar: both index the same 256-entry viridis
// table; the map's value is bilinear (exact on a linear ramp) and the bar's row is one of ~600, so
// the index may differ by one step (viridis steps are <= 4 levels per channel); PNG is lossless.
constexpr int kColourTolLevels = 8;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// Files of an unfinished atomic write (util/atomic_file.h: PATH.tmp.<pid>) left in `dir`.
int TemporariesIn(const std::string& dir) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    count += entry.path().filename().string().find(".tmp.") != std::string::npos;
  }
  return count;
}

std::string TempDir() {
  std::string dir = ::testing::TempDir() + "calibration_pictures_test";
  fs::create_directories(dir);
  return dir;
}

// A 9 x 9 grid over a 900 x 900 image: each 3 x 3 block of samples is one region of the 3 x 3
// split (sample i at x = 100 i + 49.5).
ImageGrid Grid9(double background) {
  ImageGrid g;
  g.image_width = 900, g.image_height = 900, g.cols = 9, g.rows = 9;
  g.values.assign(81, background);
  return g;
}

void SetBlock(ImageGrid* g, int bx, int by, double base) {
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) g->values[(3 * by + j) * 9 + 3 * bx + i] = base + i + 3 * j;
  }
}

TEST(CalibrationPictures, GridPixelCentres) {
  ImageGrid g;
  g.image_width = 640, g.image_height = 480, g.cols = 64, g.rows = 48;
  g.values.assign(64 * 48, 1.0);
  EXPECT_NEAR(g.PixelAt(0, 0).x(), 4.5, kExactTol);
  EXPECT_NEAR(g.PixelAt(63, 47).y(), 474.5, kExactTol);
  g.values[2 * 64 + 3] = 7.0;  // Row-major: sample (3, 2).
  EXPECT_EQ(g.At(3, 2), 7.0);
}

TEST(CalibrationPictures, WorstRegionCornerEdgeCentre) {
  struct Case {
    int bx, by;
    const char* name;
  };
  for (const Case& c : {Case{0, 0, "top-left corner"}, Case{2, 0, "top-right corner"},
                        Case{1, 0, "top edge"}, Case{2, 1, "right edge"}, Case{1, 1, "centre"},
                        Case{0, 2, "bottom-left corner"}, Case{1, 2, "bottom edge"}}) {
    ImageGrid g = Grid9(1.0);
    SetBlock(&g, c.bx, c.by, 10.0);  // Values 10..18, mean 14.
    double mean = 0;
    EXPECT_EQ(WorstRegion(g, &mean), c.name);
    EXPECT_NEAR(mean, 14.0, kExactTol) << c.name;
  }
  // NaN samples are left out of the mean: the block's 18 (its last sample) gone leaves 10..17.
  ImageGrid g = Grid9(1.0);
  SetBlock(&g, 2, 2, 10.0);
  g.values[8 * 9 + 8] = kNaN;
  double mean = 0;
  EXPECT_EQ(WorstRegion(g, &mean), "bottom-right corner");
  EXPECT_NEAR(mean, 13.5, kExactTol);
  // A finer grid than the split (a 1280 x 1024 image, 64 x 52 samples): a peak at the left edge.
  ImageGrid fine;
  fine.image_width = 1280, fine.image_height = 1024, fine.cols = 64, fine.rows = 52;
  for (int j = 0; j < fine.rows; ++j) {
    for (int i = 0; i < fine.cols; ++i) {
      const Eigen::Vector2d p = fine.PixelAt(i, j);
      fine.values.push_back(std::exp(-((p - Eigen::Vector2d(20, 512)).squaredNorm()) / 4e4));
    }
  }
  EXPECT_EQ(WorstRegion(fine, nullptr), "left edge");
}

TEST(CalibrationPictures, WorstRegionWithoutValues) {
  ImageGrid g = Grid9(kNaN);
  double mean = -1;
  EXPECT_EQ(WorstRegion(g, &mean), "");
  EXPECT_EQ(mean, -1);  // Untouched.
  EXPECT_EQ(WorstRegion(ImageGrid(), &mean), "");
}

TEST(CalibrationPictures, CoveredFractionHandMade) {
  const int w = 640, h = 480;
  // One point at the centre of every cell of the left half (cells 0..4 of 10 across).
  std::vector<Eigen::Vector2d> left;
  for (int cy = 0; cy < 10; ++cy) {
    for (int cx = 0; cx < 5; ++cx) left.emplace_back((cx + 0.5) * 64 - 0.5, (cy + 0.5) * 48 - 0.5);
  }
  EXPECT_NEAR(CoveredFraction(w, h, {left}), 0.5, kExactTol);
  // The same points split over two views, twice: still half the cells.
  std::vector<Eigen::Vector2d> a(left.begin(), left.begin() + 20), b(left.begin() + 20, left.end());
  EXPECT_NEAR(CoveredFraction(w, h, {a, b, left}), 0.5, kExactTol);
  // The image's extreme pixel centres fall in the corner cells; outside points and NaN count
  // nothing.
  EXPECT_NEAR(CoveredFraction(w, h, {{{0, 0}, {639, 479}}}), 0.02, kExactTol);
  EXPECT_NEAR(CoveredFraction(w, h, {{{-0.6, 10}, {700, 10}, {kNaN, 5}}}), 0.0, kExactTol);
  // A cell boundary: x = 63.5 is the first pixel edge of cell 1 (x + 0.5 = 64).
  EXPECT_NEAR(CoveredFraction(w, h, {{{63.49, 0}, {63.5, 0}}}), 0.02, kExactTol);
  EXPECT_NEAR(CoveredFraction(w, h, {}), 0.0, kExactTol);
  EXPECT_NEAR(CoveredFraction(0, h, {left}), 0.0, kExactTol);
}

// The ramp v = x / 10 (x = pixel column) on a 640 x 480 image.
ImageGrid Ramp() {
  ImageGrid g;
  g.image_width = 640, g.image_height = 480, g.cols = 64, g.rows = 48;
  for (int j = 0; j < g.rows; ++j) {
    for (int i = 0; i < g.cols; ++i) g.values.push_back(g.PixelAt(i, j).x() / 10.0);
  }
  return g;
}

TEST(CalibrationPictures, HeatmapSizeAndAspect) {
  const std::string dir = TempDir();
  for (int width : {960, 700}) {
    for (int image_height : {480, 1024}) {
      ImageGrid g = Ramp();
      g.image_height = image_height;
      HeatmapOptions options;
      options.title = "ramp";
      options.width_px = width;
      const std::string path = dir + "/heat_" + std::to_string(width) + ".png";
      std::string why;
      ASSERT_TRUE(WriteHeatmapPng(path, g, {{100, 100}, {300, 200}}, options, &why)) << why;
      const cv::Mat img = cv::imread(path);
      ASSERT_FALSE(img.empty());
      const FigureLayout L = ImageFigureLayout(g.image_width, g.image_height, width);
      EXPECT_EQ(img.cols, width);
      EXPECT_EQ(img.rows, L.height);
      EXPECT_NEAR(L.plot_h, L.plot_w * static_cast<double>(image_height) / 640.0, kRoundingPx);
      EXPECT_GE(L.plot_w, 0.7 * width);  // The image frame takes most of the figure.
      EXPECT_EQ(TemporariesIn(fs::path(path).parent_path().string()), 0);
    }
  }
}

TEST(CalibrationPictures, HeatmapColourMatchesColourBar) {
  const std::string dir = TempDir();
  const ImageGrid g = Ramp();
  HeatmapOptions options;
  options.title = "ramp";
  options.unit = "px";
  options.max_value = 60.0;
  options.contour_levels = {55.0};  // Away from the values checked.
  const std::string path = dir + "/ramp.png";
  std::string why;
  ASSERT_TRUE(WriteHeatmapPng(path, g, {}, options, &why)) << why;
  double lo = 0, hi = 0;
  ASSERT_TRUE(HeatmapRange(g, options, &lo, &hi));
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, 60.0);
  const cv::Mat img = cv::imread(path);
  ASSERT_FALSE(img.empty());
  const FigureLayout L = ImageFigureLayout(640, 480, options.width_px);
  ASSERT_EQ(img.rows, L.height);
  const double s = static_cast<double>(L.plot_w) / 640.0;
  for (double value : {12.0, 30.0, 45.0}) {
    // The map: the image column x = 10 value, halfway down (a row without ticks or labels).
    const double x_image = 10.0 * value;
    const int mx = L.plot_x + static_cast<int>(std::lround((x_image + 0.5) * s - 0.5));
    const int my = L.plot_y + L.plot_h / 2;
    // The bar: its row for the value, in its middle column.
    const int by = L.bar_y + static_cast<int>(std::lround((1.0 - value / hi) * L.bar_h - 0.5));
    const int bx = L.bar_x + L.bar_w / 2;
    const cv::Vec3b& map = img.at<cv::Vec3b>(my, mx);
    const cv::Vec3b& bar = img.at<cv::Vec3b>(by, bx);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(map[c], bar[c], kColourTolLevels) << "value " << value << " channel " << c;
    }
  }
  // Low and high values are far apart in colour (the check above is not trivially true).
  const cv::Vec3b low = img.at<cv::Vec3b>(L.bar_y + L.bar_h - 2, L.bar_x + L.bar_w / 2);
  const cv::Vec3b high = img.at<cv::Vec3b>(L.bar_y + 1, L.bar_x + L.bar_w / 2);
  EXPECT_GT(cv::norm(cv::Vec3d(low) - cv::Vec3d(high)), 150.0);
}

TEST(CalibrationPictures, HeatmapNaNIsGrey) {
  const std::string dir = TempDir();
  ImageGrid g = Ramp();
  for (int j = 0; j < g.rows; ++j) {
    for (int i = 0; i < 16; ++i) g.values[j * g.cols + i] = kNaN;  // Image x < 160: no value.
  }
  HeatmapOptions options;
  options.title = "ramp with a hole";
  const std::string path = dir + "/hole.png";
  std::string why;
  ASSERT_TRUE(WriteHeatmapPng(path, g, {}, options, &why)) << why;
  const cv::Mat img = cv::imread(path);
  ASSERT_FALSE(img.empty());
  const FigureLayout L = ImageFigureLayout(640, 480, options.width_px);
  const cv::Vec3b& grey = img.at<cv::Vec3b>(L.plot_y + L.plot_h / 2, L.plot_x + L.plot_w / 8);
  EXPECT_EQ(grey[0], grey[1]);
  EXPECT_EQ(grey[1], grey[2]);
  EXPECT_GT(grey[0], 120);
  EXPECT_LT(grey[0], 230);
}

TEST(CalibrationPictures, OtherFiguresSizes) {
  const std::string dir = TempDir();
  const int w = 1280, h = 720;
  std::vector<std::vector<Eigen::Vector2d>> views(3);
  std::vector<Eigen::Vector2d> pixels, residuals;
  std::vector<std::vector<double>> norms(3);
  for (int v = 0; v < 3; ++v) {
    for (int k = 0; k < 30; ++k) {
      const Eigen::Vector2d p(100 + 30 * k + 5 * v, 100 + 15 * k + 60 * v);
      const Eigen::Vector2d r(0.01 * k - 0.1, 0.2 - 0.01 * v);
      views[v].push_back(p), pixels.push_back(p), residuals.push_back(r);
      norms[v].push_back(r.norm());
    }
  }
  const FigureLayout L = ImageFigureLayout(w, h, kFigureWidthPx);
  std::string why;
  const std::string vectors = dir + "/vectors.png";
  ASSERT_TRUE(WriteResidualVectorsPng(vectors, w, h, pixels, residuals, "vectors", &why)) << why;
  cv::Mat img = cv::imread(vectors);
  EXPECT_EQ(img.cols, kFigureWidthPx);
  EXPECT_EQ(img.rows, L.height);

  const std::string coverage = dir + "/coverage.png";
  double fraction = -1;
  ASSERT_TRUE(WriteCoveragePng(coverage, w, h, views, "coverage", &fraction, &why)) << why;
  EXPECT_NEAR(fraction, CoveredFraction(w, h, views), kExactTol);
  EXPECT_GT(fraction, 0.0);
  img = cv::imread(coverage);
  EXPECT_EQ(img.cols, kFigureWidthPx);
  EXPECT_EQ(img.rows, L.height);

  const std::string per_view = dir + "/views.png";
  const std::vector<std::string> names = {"/a/very/long/folder/name/img_0001_left_camera.png",
                                          "/a/very/long/folder/name/img_0002_left_camera.png",
                                          "short"};
  ASSERT_TRUE(WriteViewResidualsPng(per_view, names, norms, "per view", &why)) << why;
  img = cv::imread(per_view);
  EXPECT_EQ(img.cols, kFigureWidthPx);
  EXPECT_GT(img.rows, 3 * 11);  // At least a row per view.
  EXPECT_LT(img.rows, 1000);    // Three views: a short figure.
}

TEST(CalibrationPictures, UnwritablePathFailsNamingIt) {
  const std::string path = TempDir() + "/no_such_folder/heat.png";
  std::string why;
  HeatmapOptions options;
  EXPECT_FALSE(WriteHeatmapPng(path, Ramp(), {}, options, &why));
  EXPECT_NE(why.find(path), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(WriteResidualVectorsPng(path, 640, 480, {{1, 1}}, {{0.1, 0}}, "t", &why));
  EXPECT_NE(why.find(path), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(WriteViewResidualsPng(path, {"a"}, {{0.1, 0.2}}, "t", &why));
  EXPECT_NE(why.find(path), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(WriteCoveragePng(path, 640, 480, {{{1, 1}}}, "t", nullptr, &why));
  EXPECT_NE(why.find(path), std::string::npos) << why;
}

TEST(CalibrationPictures, EmptyMapFails) {
  const std::string path = TempDir() + "/empty.png";
  std::string why;
  HeatmapOptions options;
  EXPECT_FALSE(WriteHeatmapPng(path, ImageGrid(), {}, options, &why));
  EXPECT_NE(why.find(path), std::string::npos) << why;
  EXPECT_NE(why.find("empty"), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(WriteHeatmapPng(path, Grid9(kNaN), {}, options, &why));
  EXPECT_NE(why.find("no finite value"), std::string::npos) << why;
  why.clear();
  ImageGrid wrong = Ramp();
  wrong.values.pop_back();
  EXPECT_FALSE(WriteHeatmapPng(path, wrong, {}, options, &why));
  EXPECT_NE(why.find(path), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(path));
  // Other figures without data.
  why.clear();
  EXPECT_FALSE(WriteViewResidualsPng(path, {}, {}, "t", &why));
  EXPECT_NE(why.find("no view"), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(WriteResidualVectorsPng(path, 640, 480, {{1, 1}}, {}, "t", &why));
  EXPECT_NE(why.find("residuals"), std::string::npos) << why;
  EXPECT_FALSE(WriteResidualVectorsPng(path, 640, 480, {}, {}, "t", nullptr));  // why may be null.
}

}  // namespace
}  // namespace calibench
