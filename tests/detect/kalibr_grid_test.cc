// Kalibr's printed AprilGrid (2-bit border, corner squares) rendered as the renderer draws it
// (sim/render.h), found and refined by FrameDetector: every tag found, no false id, and corners
// near the exact projections, sharp and blurred, with and without an EuRoC-like lens.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "detect/frame_detector.h"
#include "sim/render.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

struct GridViews {
  AprilGrid grid;
  std::vector<Rigid3> cam_from_board;
  std::vector<GrayImage> images;
};

// 12 views of Kalibr's 6 x 6 grid (tag 8.8 cm) at 752 x 480: tilts up to 50 degrees about a random
// in-plane axis, 0.55-1.0 m away (tags of ~40-70 px), every corner at least 8 px inside.
GridViews RenderKalibrViews(const CameraIntrinsics& camera, double blur_px, uint64_t seed) {
  GridViews out;
  out.grid.tag_size_m = 0.088;  // Kalibr's 6 x 6 grid.
  out.grid.black_tag_border = 2;
  out.grid.corner_squares = true;
  const auto family = TagFamily::Create("tag36h11", 2, nullptr);
  RenderOptions ro;
  ro.width = 752;
  ro.height = 480;
  ro.blur_sigma_px = blur_px;
  ro.noise_sigma_gray = 2.0;
  const auto renderer = FrameRenderer::Create(camera, ro, nullptr);
  if (!renderer || !family) return out;
  const double extent = 5 * out.grid.Pitch() + out.grid.tag_size_m;
  const Eigen::Vector3d centre(extent / 2, extent / 2, 0);
  Rng rng(seed);
  for (int attempt = 0; out.images.size() < 12 && attempt < 2000; ++attempt) {
    const double angle = rng.Uniform(0, 50.0 * M_PI / 180);
    const double axis = rng.Uniform(0, 2 * M_PI);
    const Eigen::Vector3d tilt(angle * std::cos(axis), angle * std::sin(axis),
                               rng.Uniform(-0.5, 0.5));
    const double distance = rng.Uniform(0.55, 1.0);
    const double at_y = rng.Uniform(-0.06, 0.06);  // Last first (util/random.h).
    const Eigen::Vector3d at(rng.Uniform(-0.1, 0.1), at_y, distance);
    const Rigid3 cam_from_board = FacingBoardPose(tilt, centre, at);
    bool inside = true;
    for (const Eigen::Vector3d& p : out.grid.CornersInBoard()) {
      Eigen::Vector2d pixel;
      inside &= ProjectPoint(camera, cam_from_board * p, &pixel) && pixel.x() > 8 &&
                pixel.y() > 8 && pixel.x() < ro.width - 9 && pixel.y() < ro.height - 9;
    }
    if (!inside) continue;
    GrayImage image;
    if (!renderer->Render({{out.grid, family, cam_from_board}}, &rng, &image, nullptr)) break;
    out.cam_from_board.push_back(cam_from_board);
    out.images.push_back(std::move(image));
  }
  return out;
}

struct GridScore {
  int tags = 0, expected = 0, false_ids = 0;
  std::array<int, kNumFitFailures> refused{};
  double rms_px = 0, max_px = 0;
};

GridScore Score(const GridViews& views, const CameraIntrinsics& camera,
                const FrameDetectorOptions& options) {
  GridScore s;
  std::string why;
  const auto detector = FrameDetector::Create({views.grid}, options, &why);
  EXPECT_NE(detector, nullptr) << why;
  if (!detector) return s;
  const std::vector<Eigen::Vector3d> corners = views.grid.CornersInBoard();
  double sum2 = 0;
  int n = 0;
  for (size_t v = 0; v < views.images.size(); ++v) {
    DetectionCounts counts;
    const std::vector<Observation> obs = detector->Detect(views.images[v], &counts);
    s.expected += views.grid.NumTags();
    for (int k = 0; k < kNumFitFailures; ++k) s.refused[k] += counts.refused_tags[k];
    s.tags += static_cast<int>(obs.size()) / 4;
    for (const Observation& o : obs) {
      Eigen::Vector2d truth;
      ProjectPoint(camera, views.cam_from_board[v] * corners[o.point_id], &truth);
      const double e = (o.pixel - truth).norm();
      if (e > 3.0) ++s.false_ids;
      sum2 += e * e;
      ++n;
      s.max_px = std::max(s.max_px, e);
    }
  }
  s.rms_px = n ? std::sqrt(sum2 / n) : NAN;
  return s;
}

// Measured on these views (12 per case): 99.4-100% of tags found by AprilTag 3 once the squares
// are painted out (81-84% before); the photometric fit keeps 97.9% (1 px blur) to 100% (sharp)
// (refused: raw corners that a square bent by > 1.5 px), no corner farther than 3 px from the
// truth, RMS 0.011 (sharp) to 0.013 px (1 px blur, also through the EuRoC-like lens). Tolerances:
// kMinFound is one tag per 100 below the worst measured; kMaxRmsPx 1.5x the worst RMS.
constexpr double kMinFound = 0.97;
constexpr double kMaxRmsPx = 0.02;

TEST(KalibrGrid, EveryTagFoundAndFittedWithItsSquares) {
  const CameraIntrinsics pinhole{458.0, 457.0, 90.0, 367.0, 248.0};
  const CameraIntrinsics euroc{458.0, 457.0, 90.0, 367.0, 248.0, -0.28, 0.074};
  struct Case {
    CameraIntrinsics camera;
    double blur_px;
  };
  for (const Case& c : {Case{pinhole, 0.0}, Case{pinhole, 1.0}, Case{euroc, 1.0}}) {
    const GridViews views = RenderKalibrViews(c.camera, c.blur_px, 7);
    ASSERT_EQ(views.images.size(), 12u);
    FrameDetectorOptions options;  // Photometric by default.
    if (c.camera.k1 != 0) options.camera = c.camera;
    const GridScore s = Score(views, c.camera, options);
    std::printf("k1 %.2f blur %.1f: %d of %d tags, %d corners > 3 px, rms %.4f px (max %.3f)\n",
                c.camera.k1, c.blur_px, s.tags, s.expected, s.false_ids, s.rms_px, s.max_px);
    EXPECT_GE(s.tags, kMinFound * s.expected);
    EXPECT_EQ(s.false_ids, 0);
    EXPECT_LT(s.rms_px, kMaxRmsPx);
  }
}

}  // namespace
}  // namespace calibench
