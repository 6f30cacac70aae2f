// The rendered measurement chain: render -> detect -> refine -> match, on a two-grid rig seen by a
// moving camera. Ground truth is the scene itself (exact projections of the matched points).
#include "detect/rendered_source.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>

#include "tests/common/rendered_rig.h"

namespace calibench {
namespace {

// The pooled corners of a rig of two grids at 45 degrees are not coplanar: the centred cloud's
// smallest singular value is far from zero (0 for one board, up to rounding).
TEST(Rig, TwoGridsAtAnAngleGiveNonCoplanarPoints) {
  const Rig rig = MakeRig(1.0);
  Eigen::MatrixXd cloud(rig.scene.points.size(), 3);
  for (size_t i = 0; i < rig.scene.points.size(); ++i) cloud.row(i) = rig.scene.points[i];
  const Eigen::MatrixXd centred = cloud.rowwise() - cloud.colwise().mean();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::MatrixXd>(centred).singularValues();
  EXPECT_GT(sv[2] / sv[0], 0.1);
  const std::vector<Eigen::Vector3d> one = rig.grids[0].CornersInPointsFrame();
  Eigen::MatrixXd board(one.size(), 3);
  for (size_t i = 0; i < one.size(); ++i) board.row(i) = one[i];
  const Eigen::MatrixXd c1 = board.rowwise() - board.colwise().mean();
  EXPECT_LT(Eigen::JacobiSVD<Eigen::MatrixXd>(c1).singularValues()[2], 1e-12);
}

// Bounds on noise-free frames of this rig: every tag fully in view is found,
// and the refined corners' error stays within the targets (RMS 0.05 px, bias 0.02 px).
constexpr double kRmsBoundPx = 0.05, kBiasBoundPx = 0.02;

TEST(RenderedSource, NoiseFreeRigIsDetectedAccuratelyAndMatched) {
  const Rig rig = MakeRig(1.0);
  RenderedSourceOptions options;
  options.frame_rate_hz = 5;
  std::string why;
  const auto source = RenderedSource::Create(rig.scene, rig.grids, options, 7, &why);
  ASSERT_NE(source, nullptr) << why;
  const DetectionStats& s = source->stats();
  EXPECT_EQ(s.frames, 5);
  EXPECT_EQ(s.frames_without_detections, 0);
  EXPECT_GE(s.DetectionRate(), 1.0);
  EXPECT_EQ(s.unknown_tags, 0);
  EXPECT_LT(s.rms_px, kRmsBoundPx);
  EXPECT_LT(std::abs(s.bias_x_px), kBiasBoundPx);
  EXPECT_LT(std::abs(s.bias_y_px), kBiasBoundPx);
  std::printf("rig: %ld corners, RMS %.4f px, bias (%.4f, %.4f) px, p95 %.4f px, %ld unrefined\n",
              s.corners, s.rms_px, s.bias_x_px, s.bias_y_px, s.p95_px, s.unrefined_tags);
  // Both grids are matched, and every entry is the point it says (independent projection).
  Frame frame;
  source->GetFrame(0, &frame);
  bool saw_first = false, saw_second = false;
  const Rigid3 cam_from_parent = rig.scene.CamFromParent();
  for (size_t i = 0; i < frame.pixels.size(); ++i) {
    saw_first |= frame.point_ids[i] < 80;
    saw_second |= frame.point_ids[i] >= 80;
    Eigen::Vector2d exact;
    ASSERT_TRUE(
        ProjectPoint(rig.scene.intrinsics, cam_from_parent * frame.points_in_parent[i], &exact));
    EXPECT_LT((frame.pixels[i] - exact).norm(), 0.25) << "point " << frame.point_ids[i];
  }
  EXPECT_TRUE(saw_first && saw_second);
}

// Each frame depends only on (trial seed, frame index): any thread count gives the same frames.
TEST(RenderedSource, FramesDoNotDependOnTheThreadCount) {
  const Rig rig = MakeRig(0.4);
  RenderedSourceOptions options;
  options.frame_rate_hz = 10;
  options.render.noise_sigma_gray = 2;
  options.threads = 1;
  const auto one = RenderedSource::Create(rig.scene, rig.grids, options, 11, nullptr);
  options.threads = 2;
  const auto two = RenderedSource::Create(rig.scene, rig.grids, options, 11, nullptr);
  options.threads = 1;
  const auto other_seed = RenderedSource::Create(rig.scene, rig.grids, options, 12, nullptr);
  ASSERT_TRUE(one && two && other_seed);
  ASSERT_EQ(one->NumFrames(), 4);
  ASSERT_EQ(two->NumFrames(), 4);
  bool differs = false;
  for (int k = 0; k < one->NumFrames(); ++k) {
    Frame a, b, c;
    one->GetFrame(k, &a);
    two->GetFrame(k, &b);
    other_seed->GetFrame(k, &c);
    EXPECT_EQ(a.point_ids, b.point_ids);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) EXPECT_EQ(a.pixels[i], b.pixels[i]);
    differs |= a.pixels.size() != c.pixels.size() || a.pixels[0] != c.pixels[0];
  }
  EXPECT_TRUE(differs);  // The noise really comes from the seed.
}

// A camera that sees no board: every frame is counted as empty; nothing fails.
TEST(RenderedSource, FramesWithoutDetectionsAreCountedNotFatal) {
  Rig rig = MakeRig(0.3);
  for (AprilGrid& g : rig.grids) g.points_from_board.translation.z() += 50.0;  // Far above.
  rig.scene.points.clear();
  for (const AprilGrid& g : rig.grids) {
    const std::vector<Eigen::Vector3d> c = g.CornersInPointsFrame();
    rig.scene.points.insert(rig.scene.points.end(), c.begin(), c.end());
  }
  RenderedSourceOptions options;
  options.frame_rate_hz = 10;
  std::string why;
  const auto source = RenderedSource::Create(rig.scene, rig.grids, options, 1, &why);
  ASSERT_NE(source, nullptr) << why;
  EXPECT_EQ(source->stats().frames, 3);
  EXPECT_EQ(source->stats().frames_without_detections, 3);
  EXPECT_EQ(source->stats().tags_expected, 0);
}

TEST(FrameDetector, RejectsTargetsItCannotAttribute) {
  AprilGrid a, b;
  b.first_id = 30;  // Overlaps a's ids 0..35.
  std::string why;
  EXPECT_EQ(FrameDetector::Create({a, b}, FrameDetectorOptions(), &why), nullptr);
  EXPECT_NE(why.find("shares tag ids"), std::string::npos) << why;
  b.first_id = 36;
  b.family = "tagStandard41h12";
  EXPECT_EQ(FrameDetector::Create({a, b}, FrameDetectorOptions(), &why), nullptr);
  EXPECT_NE(why.find("one detector decodes one family"), std::string::npos) << why;
  b.family = "tag36h11";
  const auto d = FrameDetector::Create({a, b}, FrameDetectorOptions(), &why);
  ASSERT_NE(d, nullptr) << why;
  EXPECT_EQ(d->NumPoints(), 288);
  EXPECT_EQ(d->PointId(37, 2), 144 + 4 + 2);
  EXPECT_EQ(d->PointId(500, 0), -1);
}

}  // namespace
}  // namespace calibench
