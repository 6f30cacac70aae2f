// Kalibr AprilGrids in real frames (CTest label "data"): ../shared/data/aprilgrid-frames
// (aprilgrid-rs's test set: EuRoC and TUM VI calibration frames, SOURCE.md), read through
// detect --images with tests/fixtures/aprilgrid_6x6.yaml (a copy of configs/targets/).
// docs/aprilgrid_frames.md has the study these figures come from (tools/aprilgrid_frames.py).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/calib3d.hpp>

#include "calib/calibrate.h"
#include "calib/calibrate_report.h"
#include "calib/detect_images.h"
#include "calib/image_points.h"
#include "calib/model_select.h"
#include "io/target_io.h"
#include "tests/common/test_data.h"

namespace calibench {
namespace {

const std::string kTarget =
    std::string(CALIBENCH_SOURCE_DIR) + "/tests/fixtures/aprilgrid_6x6.yaml";

// Tags found per frame, measured (Debian's AprilTag 3.3 and OpenCV 4.6). Required: all but
// kTagsSlack of them, room for a corner-case quad that another library build fits differently;
// EuRoC's bound, >= 34 of 36, is one below OpenCV ArUco's 35 there (aprilgrid-frames/SOURCE.md).
constexpr int kTagsSlack = 2;
const std::map<std::string, int> kMeasuredTags = {{"EuRoC.png", 36}, {"TUM_VI.png", 35},
                                                  {"r45.png", 23},   {"right.png", 18},
                                                  {"top.png", 24},   {"top_right.png", 27}};

// Pitch / size from the cross ratio of four collinear corners (x = 0, 1, rho, rho + 1 along the
// edges of two neighbouring tags: CR = rho^2 / (rho^2 - 1)), a projective invariant needing no
// calibration. Measured medians 1.300-1.302 on every frame; Kalibr's nominal 1 + tagSpacing =
// 1.30. 0.005 is 5x the spread of the frames' medians and 25x smaller than the 1.42 that a
// homography fit once suggested (SOURCE.md).
constexpr double kNominalPitch = 1.30, kPitchTol = 0.005;
// EuRoC undistorted by its published cam0 calibration, one plane homography for the 6x6 grid
// at pitch/size 1.30: RMS measured 0.275 px (0.26 px for OpenCV aruco's corners of the same
// tags). 0.35 px leaves room for the library build, not for a wrong spacing (1.32: 0.46 px).
constexpr double kEurocHomographyRmsPx = 0.35;

// A folder (under the test's temp dir) of links to the five 1024 x 1024 TUM VI frames:
// calibrate needs one image size.
std::string TumViFolder(const std::string& name) {
  std::string dir = testing::TempDir() + "/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* frame : {"TUM_VI.png", "r45.png", "right.png", "top.png", "top_right.png"}) {
    std::filesystem::create_symlink(kSharedDataDir + "/aprilgrid-frames/" + frame,
                                    dir + "/" + frame);
  }
  return dir;
}

// The TUM VI folder's target points through calibrate --images' reader, for `lens`.
testing::AssertionResult LoadTumViPoints(const std::string& name, LensFamily lens, PointData* data,
                                         ImageFolderReport* report) {
  CalibrationTarget target;
  std::string why;
  if (!LoadTargetYaml(kTarget, &target, &why)) return testing::AssertionFailure() << why;
  std::vector<int> used;
  if (!LoadImagePoints(TumViFolder(name), target, data, report, &used, &why,
                       {lens, std::nullopt, std::nullopt})) {
    return testing::AssertionFailure() << why;
  }
  return testing::AssertionSuccess();
}

using Corners = std::map<int, std::map<int, Eigen::Vector2d>>;  // tag -> corner -> pixel.

Corners ByTag(const ImageCorners& image) {
  Corners c;
  for (const ImageCorners::Corner& k : image.corners) {
    c[k.tag_id][k.corner] = Eigen::Vector2d(k.u_px, k.v_px);
  }
  return c;
}

double MedianCrossRatioPitch(const Corners& tags) {
  std::vector<double> rhos;
  for (const auto& [tag, corners] : tags) {
    const int c = tag % 6;
    // Right neighbour: bottom (0, 1) and top (3, 2) edges; upper neighbour: left (0, 3), right
    // (1, 2) edges.
    const std::pair<int, std::array<std::pair<int, int>, 2>> pairs[2] = {
        {c < 5 ? tag + 1 : -1, {{{0, 1}, {3, 2}}}}, {tag + 6, {{{0, 3}, {1, 2}}}}};
    for (const auto& [other, edges] : pairs) {
      if (other < 0 || tags.count(other) == 0) continue;
      for (const auto& [a, b] : edges) {
        const Eigen::Vector2d x[4] = {corners.at(a), corners.at(b), tags.at(other).at(a),
                                      tags.at(other).at(b)};
        const auto d = [&](int i, int j) { return (x[i] - x[j]).norm(); };
        const double cr = d(2, 0) * d(3, 1) / (d(2, 1) * d(3, 0));
        if (cr > 1) rhos.push_back(std::sqrt(cr / (cr - 1)));
      }
    }
  }
  if (rhos.empty()) return 0;
  std::nth_element(rhos.begin(), rhos.begin() + rhos.size() / 2, rhos.end());
  return rhos[rhos.size() / 2];
}

TEST(AprilGridFrames, KalibrGridsAreFoundWithTheNominalSpacing) {
  REQUIRE_SHARED_DATA("aprilgrid-frames");
  CalibrationTarget target;
  std::string why;
  ASSERT_TRUE(LoadTargetYaml(kTarget, &target, &why)) << why;
  std::vector<ImageCorners> images;
  ASSERT_TRUE(DetectImageCorners(kSharedDataDir + "/aprilgrid-frames", target, &images, &why))
      << why;
  int checked = 0;
  for (const ImageCorners& image : images) {
    const auto measured = kMeasuredTags.find(image.file);
    if (measured == kMeasuredTags.end()) continue;  // iphone, two_boards: other grids.
    ++checked;
    ASSERT_TRUE(image.readable) << image.file << ": " << image.note;
    std::printf("%s: %d tags%s\n", image.file.c_str(), image.tags,
                image.note.empty() ? "" : (" (" + image.note + ")").c_str());
    EXPECT_GE(image.tags, measured->second - kTagsSlack) << image.file;
    EXPECT_EQ(image.unknown_tags, 0) << image.file;
    EXPECT_EQ(image.corners.size(), 4u * image.tags) << image.file;
    const double pitch = MedianCrossRatioPitch(ByTag(image));
    std::printf("  cross-ratio pitch/size %.4f\n", pitch);
    EXPECT_NEAR(pitch, kNominalPitch, kPitchTol) << image.file;
    if (image.file == "EuRoC.png") {
      EXPECT_GE(image.tags, 34);
      std::vector<cv::Point2f> pixels, board;
      for (const ImageCorners::Corner& c : image.corners) {
        pixels.emplace_back(static_cast<float>(c.u_px), static_cast<float>(c.v_px));
        const int r = c.tag_id / 6, col = c.tag_id % 6;
        const double dx = c.corner == 1 || c.corner == 2, dy = c.corner >= 2;
        board.emplace_back(static_cast<float>(col * kNominalPitch + dx),
                           static_cast<float>(r * kNominalPitch + dy));
      }
      const cv::Matx33d k(458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1);
      const std::vector<double> dist = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
      std::vector<cv::Point2f> undistorted;
      cv::undistortPoints(pixels, undistorted, k, dist, cv::noArray(), k);
      const cv::Mat h = cv::findHomography(board, undistorted, 0);
      ASSERT_FALSE(h.empty());
      std::vector<cv::Point2f> projected;
      cv::perspectiveTransform(board, projected, h);
      double sum_sq = 0;
      for (size_t i = 0; i < projected.size(); ++i) {
        const cv::Point2f e = projected[i] - undistorted[i];
        sum_sq += e.dot(e);
      }
      const double rms = std::sqrt(sum_sq / projected.size());
      std::printf("  EuRoC homography RMS at pitch/size %.2f: %.3f px\n", kNominalPitch, rms);
      EXPECT_LT(rms, kEurocHomographyRmsPx);
    }
  }
  EXPECT_EQ(checked, 6);
}

// calibrate --images reads the same frames the same way, 16-bit ones included (a folder of the
// five 1024 x 1024 TUM VI frames: calibrate needs one image size).
TEST(AprilGridFrames, CalibrateReadsTheSixteenBitFrames) {
  REQUIRE_SHARED_DATA("aprilgrid-frames");
  PointData data;
  ImageFolderReport report;
  ASSERT_TRUE(LoadTumViPoints("tum_vi_frames", LensFamily::kRadTan, &data, &report));
  ASSERT_EQ(report.images.size(), 5u);
  EXPECT_EQ(report.used, 5);
  EXPECT_EQ(data.image_width, 1024);
  for (const ImageResult& r : report.images) {
    EXPECT_GE(r.points, 4 * (kMeasuredTags.at(r.file) - kTagsSlack)) << r.file << ": " << r.reason;
    EXPECT_NE(r.reason.find("16-bit"), std::string::npos) << r.reason;
  }
}

// The five TUM VI frames calibrated as a fisheye (pinhole-equi) from scratch, against TUM VI's
// published cam0 calibration (512 x 512, Kannala-Brandt: fx 190.97847715, fy 190.97330705,
// cx 254.93170606, cy 256.89744290, k 0.0034823894, 0.00071503485, -0.0020532361,
// 0.00020293674), taken to these 1024 x 1024 frames (x2, and +0.5 px for the binning's pixel
// centres: c_1024 = 2 c_512 + 0.5).
// - The published camera, kept fixed, fits every frame to 0.15 px RMS (measured 0.07-0.11).
// - Our own fit (5 frames only; measured f 381.99 +- 0.22, c (509.93, 514.27) +- 0.1, RMS 0.090
//   px) is within 0.1 % of the published focal lengths and 1 px of its principal point: the
//   published one comes from another recording, so agreement, not identity, is the test.
constexpr double kTumFrameRmsPx = 0.15;
constexpr double kTumFocalRelTol = 1e-3;
constexpr double kTumCentrePx = 1.0;

TEST(AprilGridFrames, TumViFramesCalibrateAsTheirPublishedFisheye) {
  REQUIRE_SHARED_DATA("aprilgrid-frames");
  PointData data;
  ImageFolderReport report;
  ASSERT_TRUE(LoadTumViPoints("tum_vi_fisheye", LensFamily::kEquidistant, &data, &report));
  CameraFile published;
  CameraIntrinsics& p = published.intrinsics;
  p.family = LensFamily::kEquidistant;
  p.fku_px = 2 * 190.97847715128717, p.fkv_px = 2 * 190.9733070521226;
  p.u0_px = 2 * 254.93170605935475 + 0.5, p.v0_px = 2 * 256.8974428996504 + 0.5;
  p.k1 = 0.0034823894022493434, p.k2 = 0.0007150348452162257;
  p.k3 = -0.0020532361418706202, p.k4 = 0.00020293673591811182;
  published.lens_model = LensModel::kPinholeEqui;
  published.image_width = published.image_height = 1024;
  CalibrateOptions evaluate;
  evaluate.model = LensModel::kPinholeEqui;
  evaluate.init = published;
  evaluate.evaluate_only = true;
  const CalibrateReport given = CalibrateFromPoints(data, evaluate);
  ASSERT_TRUE(given.IsUsable()) << given.ceres.message;
  ASSERT_EQ(given.ceres.view_rms_px.size(), 5u);
  for (double rms : given.ceres.view_rms_px) EXPECT_LT(rms, kTumFrameRmsPx);

  CalibrateOptions fit;
  fit.model = LensModel::kPinholeEqui;
  const CalibrateReport ours = CalibrateFromPoints(data, fit);
  ASSERT_TRUE(ours.IsUsable()) << ours.ceres.message;
  const CameraIntrinsics& k = ours.ceres.intrinsics;
  EXPECT_NEAR(k.fku_px, p.fku_px, kTumFocalRelTol * p.fku_px);
  EXPECT_NEAR(k.fkv_px, p.fkv_px, kTumFocalRelTol * p.fkv_px);
  EXPECT_NEAR(k.u0_px, p.u0_px, kTumCentrePx);
  EXPECT_NEAR(k.v0_px, p.v0_px, kTumCentrePx);
  for (double rms : ours.ceres.view_rms_px) EXPECT_LT(rms, kTumFrameRmsPx);
  EXPECT_LE(ours.ceres.rms_reproj_px, given.ceres.rms_reproj_px);  // Its own optimum.

  // Five views disagree far more than their residuals say: the leave-one-view-out std of f.ku
  // that calibrate prints beside the formal one exceeds it kJackknifeOverFormal times or more
  // (measured: 1.19 against 0.23 px on this first pass; 1.39 against 0.15 px after calibrate's
  // re-fits through the lens, where the published f.ku is 0.37 px, 2.5 formal std, away), and the
  // published f.ku lies within kPublishedInJackknifeStd jackknife std of ours.
  constexpr double kJackknifeOverFormal = 3.0, kPublishedInJackknifeStd = 2.0;
  CalibrateReport with_jackknife = ours;
  AddJackknife(data, fit, &with_jackknife);
  ASSERT_TRUE(with_jackknife.jackknife && with_jackknife.jackknife->IsUsable());
  const double jack_std = with_jackknife.jackknife->intrinsics_std[0];
  const double formal_std = ours.ceres.intrinsics_std[0];
  std::printf("TUM VI f.ku %.3f: formal std %.3f, jackknife std %.3f, published %.3f\n", k.fku_px,
              formal_std, jack_std, p.fku_px);
  EXPECT_GT(jack_std, kJackknifeOverFormal * formal_std);
  EXPECT_LT(std::abs(k.fku_px - p.fku_px), kPublishedInJackknifeStd * jack_std);
}

// The five TUM VI frames calibrated from scratch by each omnidirectional family (the wide start,
// then ceres), against pinhole-equi (corners fitted with each family's curved edges): each fits
// as well or better, within the RMS's own noise (the next test's rule, kRmsNoiseSigmas std of an
// RMS of m residuals: 1.056 x here, tighter than 10 %). Measured RMS
// (printed): pinhole-equi 0.0905 (cv::fisheye fails on these frames: the wide start), unified
// 0.0905, eucm 0.0917, double-sphere 0.0909 px; eucm alpha 0.6284 beta 1.0461 and the double
// sphere's xi -0.179 alpha 0.592 are basalt's published TUM VI values (0.6291, 1.0418; -0.18,
// 0.59) within a few thousandths.
// Mutation caught: curved edges for equidistant only (ImageDetectorOptions): the other families'
// corners then have straight edges and fit at 0.163 px, 80 % above pinhole-equi's.
TEST(AprilGridFrames, TumViFramesCalibrateByEveryOmnidirectionalFamily) {
  REQUIRE_SHARED_DATA("aprilgrid-frames");
  double equi_rms = 0;
  for (LensModel model :
       {LensModel::kPinholeEqui, LensModel::kUnified, LensModel::kEucm, LensModel::kDoubleSphere}) {
    PointData data;
    ImageFolderReport report;
    const std::string name = std::string("tum_vi_") + ToString(model);
    ASSERT_TRUE(LoadTumViPoints(name, FamilyOf(model), &data, &report));
    CalibrateOptions options;
    options.model = model;
    const CalibrateReport fit = CalibrateFromPoints(data, options);
    ASSERT_TRUE(fit.IsUsable()) << ToString(model) << ": " << fit.ceres.message;
    EXPECT_EQ(fit.ceres.view_rms_px.size(), 5u) << ToString(model);
    std::cout << FormatCalibrateReport(fit, data);
    std::printf("[ measured ] %s: RMS %.4f px (%s)\n", ToString(model), fit.ceres.rms_reproj_px,
                fit.zhang.message.c_str());
    if (model == LensModel::kPinholeEqui) {
      equi_rms = fit.ceres.rms_reproj_px;
    } else {
      double m = 0;  // Residuals: 2 per point.
      for (const View& v : data.views) m += 2.0 * v.pixels.size();
      EXPECT_LE(fit.ceres.rms_reproj_px, (1 + kRmsNoiseSigmas / std::sqrt(2 * m)) * equi_rms)
          << ToString(model);
    }
  }
}

// The same frames as `calibrate --model auto` compares them: the four fisheye-capable families
// fitted on the same corners (the first pass, curved edges through the unified family, as auto
// detects), each scored on views it was not fitted to (leave-one-view-out: 5 folds of 5 views).
// "As good as pinhole-equi" is held to the rule auto uses for "within noise": an RMS of m
// Gaussian residuals has a relative std of 1 / sqrt(2 m), so a fit is as good when its RMS is
// at most pinhole-equi's times (1 + kRmsNoiseSigmas / sqrt(2 m)) (1.056 here, m = 1440). Two fits
// of the same corners are not independent draws, so the bound is loose (measured at most 1.013x);
// it is the rule a user's `--model auto` applies.
// Measured in-sample: pinhole-equi 0.0905, unified 0.0905, eucm 0.0917, double-sphere 0.0909 px.
// Held out, the criterion that charges a model for its parameters: double-sphere 0.1166 and
// eucm 0.1217 px (6 parameters) predict the left-out views better than pinhole-equi (8) at
// 0.1263 px; unified (9: xi, f and k1 barely separable in 5 views) at 0.1393 px worse.
TEST(AprilGridFrames, TumViFramesHeldOutByEveryFisheyeFamily) {
  REQUIRE_SHARED_DATA("aprilgrid-frames");
  PointData data;
  ImageFolderReport report;
  ASSERT_TRUE(LoadTumViPoints("tum_vi_auto", LensFamily::kUnified, &data, &report));
  ModelSelectOptions options;
  options.candidates = {LensModel::kPinholeEqui, LensModel::kUnified, LensModel::kEucm,
                        LensModel::kDoubleSphere};
  const ModelSelection selection = SelectLensModel(data, options);
  std::cout << FormatModelSelection(selection);
  ASSERT_EQ(selection.scores.size(), 4u);
  for (const ModelScore& s : selection.scores) {
    ASSERT_TRUE(s.fitted && s.cross_validated && s.comparable)
        << ToString(s.model) << ": " << s.note;
  }
  const ModelScore& equi = selection.scores[0];
  double m = 0;  // Residuals: 2 per point.
  for (const View& v : data.views) m += 2.0 * v.pixels.size();
  const double as_good = 1 + kRmsNoiseSigmas / std::sqrt(2 * m);
  for (const ModelScore& s : selection.scores) {
    EXPECT_LE(s.rms_px, as_good * equi.rms_px) << ToString(s.model);
  }
  for (int i : {2, 3}) {  // eucm, double-sphere.
    EXPECT_LE(selection.scores[i].cv_rms_px, equi.cv_rms_px) << ToString(selection.scores[i].model);
  }
  // The pick is one of the 6-parameter families, which predict best.
  ASSERT_TRUE(selection.IsUsable());
  EXPECT_EQ(selection.scores[selection.chosen].free_params, 6) << selection.reason;
}

}  // namespace
}  // namespace calibench
