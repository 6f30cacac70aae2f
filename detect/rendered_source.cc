#include "detect/rendered_source.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "core/random.h"

namespace calibench {
namespace {

// Per-frame detection bookkeeping, merged in frame order after the parallel part.
struct FrameResult {
  Frame frame;
  DetectionCounts counts;
  int tags_expected = 0;
  std::vector<Eigen::Vector2d> errors;  // Detected minus exact, per corner.
  std::string error;                    // Non-empty: rendering failed.
};

// Tags of the grids whose four corners project at least `margin_px` inside the image, on the
// side of the board that faces the camera.
int ExpectedTags(const SceneTruth& scene, const std::vector<BoardView>& views, int width,
                 int height) {
  constexpr double kMarginPx = 2.0;
  int expected = 0;
  for (const BoardView& view : views) {
    if (!(view.cam_from_board.Inverse().translation.z() > 0)) continue;  // Seen from behind.
    const std::vector<Eigen::Vector3d> corners = view.grid.CornersInBoard();
    for (size_t t = 0; t + 3 < corners.size(); t += 4) {
      bool inside = true;
      for (size_t k = t; k < t + 4 && inside; ++k) {
        Eigen::Vector2d pixel;
        inside = ProjectPoint(scene.intrinsics, view.cam_from_board * corners[k], &pixel) &&
                 pixel.x() >= kMarginPx - 0.5 && pixel.y() >= kMarginPx - 0.5 &&
                 pixel.x() <= width - 0.5 - kMarginPx && pixel.y() <= height - 0.5 - kMarginPx;
      }
      expected += inside;
    }
  }
  return expected;
}

}  // namespace

bool RenderedSourceOptions::Check(std::string* why) const {
  if (!(frame_rate_hz > 0 && std::isfinite(frame_rate_hz))) {
    if (why) *why = "frame_rate_hz must be > 0, got " + std::to_string(frame_rate_hz);
    return false;
  }
  if (threads < 0) {
    if (why) *why = "threads must be >= 0 (0: all cores)";
    return false;
  }
  return render.Check(why) && detection.Check(why);
}

std::vector<BoardView> BoardViewsAt(const SceneTruth& scene, const std::vector<AprilGrid>& grids,
                                    const std::vector<std::shared_ptr<const TagFamily>>& families,
                                    double t) {
  const Rigid3 cam_from_points = scene.CamFromParent() * scene.ParentFromPoints(t);
  std::vector<BoardView> views(grids.size());
  for (size_t g = 0; g < grids.size(); ++g) {
    views[g].grid = grids[g];
    views[g].family = families[g];
    views[g].cam_from_board = cam_from_points * grids[g].points_from_board;
  }
  return views;
}

std::unique_ptr<RenderedSource> RenderedSource::Create(const SceneTruth& scene,
                                                       const std::vector<AprilGrid>& grids,
                                                       const RenderedSourceOptions& options,
                                                       uint64_t trial_seed, std::string* why) {
  if (!options.Check(why) || !scene.Check(why)) return nullptr;
  // Validates the target (one family, distinct ids) before any work.
  if (!FrameDetector::Create(grids, options.detection, why)) return nullptr;
  std::vector<Eigen::Vector3d> corners;
  for (const AprilGrid& g : grids) {
    const std::vector<Eigen::Vector3d> c = g.CornersInPointsFrame();
    corners.insert(corners.end(), c.begin(), c.end());
  }
  if (corners.size() != scene.points.size()) {
    if (why) *why = "the scene's points are not the grids' corners";
    return nullptr;
  }
  std::vector<std::shared_ptr<const TagFamily>> families;
  for (const AprilGrid& g : grids) {
    families.push_back(TagFamily::Create(g.family, why));
    if (!families.back()) return nullptr;
  }
  const auto renderer = FrameRenderer::Create(scene.intrinsics, options.render, why);
  if (!renderer) return nullptr;

  std::unique_ptr<RenderedSource> source(new RenderedSource());
  source->scene_ = scene;
  const double duration = scene.duration_s;
  const long count = static_cast<long>(std::ceil(duration * options.frame_rate_hz - 1e-9));
  for (long k = 0; k < count; ++k) {
    source->breakpoints_.push_back(static_cast<double>(k) / options.frame_rate_hz);
  }
  std::vector<FrameResult> results(source->breakpoints_.size());
  source->breakpoints_.push_back(duration);

  std::atomic<size_t> next{0};
  auto worker = [&] {
    std::string error;
    const auto detector = FrameDetector::Create(grids, options.detection, &error);
    GrayImage image;
    for (size_t k = next++; k < results.size(); k = next++) {
      FrameResult& r = results[k];
      const double t = source->breakpoints_[k];
      const std::vector<BoardView> views = BoardViewsAt(scene, grids, families, t);
      Rng noise(TrialSeed(trial_seed, k), RngStream::kPixelNoise);
      if (!renderer->Render(views, &noise, &image, &r.error)) continue;
      r.tags_expected = ExpectedTags(scene, views, image.width, image.height);
      const Rigid3 parent_from_points = scene.ParentFromPoints(t);
      const Rigid3 cam_from_points = scene.CamFromParent() * parent_from_points;
      r.frame.time_s = t;
      for (const Observation& o : detector->Detect(image, &r.counts)) {
        r.frame.point_ids.push_back(o.point_id);
        r.frame.points_in_parent.push_back(parent_from_points * scene.points[o.point_id]);
        r.frame.pixels.push_back(o.pixel);
        Eigen::Vector2d exact;
        if (ProjectPoint(scene.intrinsics, cam_from_points * scene.points[o.point_id], &exact)) {
          r.errors.push_back(o.pixel - exact);
        }
      }
    }
  };
  int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, static_cast<int>(std::max<size_t>(1, results.size())));
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();

  DetectionStats& stats = source->stats_;
  std::vector<double> norms;
  Eigen::Vector2d bias = Eigen::Vector2d::Zero();
  double sum_sq = 0;
  for (FrameResult& r : results) {
    if (!r.error.empty()) {
      if (why) *why = "frame at t = " + std::to_string(r.frame.time_s) + " s: " + r.error;
      return nullptr;
    }
    ++stats.frames;
    stats.frames_without_detections += r.frame.pixels.empty();
    stats.tags_expected += r.tags_expected;
    stats.tags_detected += r.counts.tags;
    stats.unknown_tags += r.counts.unknown_tags;
    for (const Eigen::Vector2d& e : r.errors) {
      bias += e;
      sum_sq += e.squaredNorm();
      norms.push_back(e.norm());
    }
    source->frames_.push_back(std::move(r.frame));
  }
  stats.corners = static_cast<long>(norms.size());
  if (!norms.empty()) {
    const double n = static_cast<double>(norms.size());
    stats.rms_px = std::sqrt(sum_sq / n);
    stats.bias_x_px = bias.x() / n;
    stats.bias_y_px = bias.y() / n;
    const size_t p95 = std::min(norms.size() - 1, static_cast<size_t>(std::ceil(0.95 * n)) - 1);
    std::nth_element(norms.begin(), norms.begin() + p95, norms.end());
    stats.p95_px = norms[p95];
  }
  return source;
}

}  // namespace calibench
