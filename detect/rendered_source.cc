#include "detect/rendered_source.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "util/parallel_for.h"
#include "util/random.h"

namespace calibench {
namespace {

// Per-frame detection bookkeeping, merged in frame order after the parallel part.
struct FrameResult {
  Frame frame;
  DetectionCounts counts;
  int tags_expected = 0;
  std::vector<Eigen::Vector2d> errors;   // Detected minus exact, per corner.
  std::vector<Eigen::Vector2d> outward;  // Per corner: unit, from its tag's centre (projected).
  std::vector<double> crlb_px;           // Per corner: Observation::crlb_px.
  std::string error;                     // Non-empty: rendering failed.
};

}  // namespace

std::vector<std::vector<bool>> TagsInView(const CameraIntrinsics& intrinsics,
                                          const std::vector<BoardView>& views, int width,
                                          int height) {
  constexpr double kMarginPx = 2.0;
  std::vector<std::vector<bool>> in_view;
  for (const BoardView& view : views) {
    const std::vector<Eigen::Vector3d> corners = view.grid.CornersInBoard();
    std::vector<bool> tags(corners.size() / 4, false);
    const bool facing = view.cam_from_board.Inverse().translation.z() > 0;
    for (size_t t = 0; facing && t < tags.size(); ++t) {
      bool inside = true;
      for (size_t k = 4 * t; k < 4 * t + 4 && inside; ++k) {
        Eigen::Vector2d pixel;
        inside = ProjectPoint(intrinsics, view.cam_from_board * corners[k], &pixel) &&
                 pixel.x() >= kMarginPx - 0.5 && pixel.y() >= kMarginPx - 0.5 &&
                 pixel.x() <= width - 0.5 - kMarginPx && pixel.y() <= height - 0.5 - kMarginPx;
      }
      tags[t] = inside;
    }
    in_view.push_back(tags);
  }
  return in_view;
}

void DetectionStatsAccumulator::AddFrame(int tags_expected, const DetectionCounts& counts,
                                         bool no_detection) {
  ++stats_.frames;
  stats_.frames_without_detections += no_detection;
  stats_.tags_expected += tags_expected;
  stats_.tags_detected += counts.tags;
  stats_.unknown_tags += counts.unknown_tags;
  stats_.unrefined_tags += counts.unrefined_tags;
  stats_.unrefined_copy_tags += counts.unrefined_copy_tags;
  stats_.refused_tags += counts.RefusedTags();
  for (int f = 0; f < kNumFitFailures; ++f) stats_.refused_by_reason[f] += counts.refused_tags[f];
  stats_.border_tags += counts.border_tags;
  stats_.predicted_tags += counts.predicted_tags;
  stats_.refitted_tags += counts.refitted_tags;
  stats_.refused_predictions += counts.refused_predictions;
  stats_.covered_tags += counts.covered_tags;
}

void DetectionStatsAccumulator::AddCornerError(const Eigen::Vector2d& e,
                                               const Eigen::Vector2d& outward, double crlb_px) {
  if (std::isfinite(crlb_px)) {
    crlb_sq_sum_ += crlb_px * crlb_px;
    ++crlb_count_;
  }
  sum_ += e;
  sum_radial_tangent_ +=
      Eigen::Vector2d(e.dot(outward), e.dot(Eigen::Vector2d(-outward.y(), outward.x())));
  sum_sq_ += e.squaredNorm();
  norms_.push_back(e.norm());
}

DetectionStats DetectionStatsAccumulator::Finish() const {
  DetectionStats stats = stats_;
  stats.corners = static_cast<long>(norms_.size());
  if (norms_.empty()) {
    stats.bias_radial_px = stats.bias_tangent_px = std::numeric_limits<double>::quiet_NaN();
    return stats;
  }
  const double n = static_cast<double>(norms_.size());
  stats.rms_px = std::sqrt(sum_sq_ / n);
  if (crlb_count_ > 0) stats.crlb_rms_px = std::sqrt(crlb_sq_sum_ / crlb_count_);
  stats.bias_x_px = sum_.x() / n;
  stats.bias_y_px = sum_.y() / n;
  stats.bias_radial_px = sum_radial_tangent_.x() / n;
  stats.bias_tangent_px = sum_radial_tangent_.y() / n;
  std::vector<double> norms = norms_;
  const size_t p95 = std::min(norms.size() - 1, static_cast<size_t>(std::ceil(0.95 * n)) - 1);
  std::nth_element(norms.begin(), norms.begin() + p95, norms.end());
  stats.p95_px = norms[p95];
  return stats;
}

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

namespace {

// A worker's detector (FrameDetector is not thread-safe) and scratch buffers.
struct WorkerState {
  std::unique_ptr<FrameDetector> detector;
  GrayImage image;
  std::vector<BoardView> views;
};

// Which frame: the trial's seed, the frame's index k and its time t (s).
struct FrameId {
  uint64_t trial_seed;
  int k;
  double t;
};

// Frame k at time t: rendered, the tags a detector should find counted, detected, and each
// detected corner's error against its exact projection (with its tag's outward direction).
// r->error says why rendering failed.
void RenderAndDetect(const SceneTruth& scene, const SceneRenderer& renderer, const FrameId& id,
                     WorkerState* state, FrameResult* r) {
  const double t = id.t;
  GrayImage* image = &state->image;
  std::vector<BoardView>* views = &state->views;
  if (!renderer.Render(t, id.trial_seed, id.k, image, views, &r->error)) return;
  const CameraIntrinsics intrinsics = scene.IntrinsicsAt(t);
  for (const std::vector<bool>& grid :
       TagsInView(intrinsics, *views, image->width, image->height)) {
    r->tags_expected += static_cast<int>(std::count(grid.begin(), grid.end(), true));
  }
  const Rigid3 parent_from_points = scene.ParentFromPoints(t);
  const Rigid3 cam_from_points = scene.CamFromParentAt(t) * parent_from_points;
  r->frame.time_s = t;
  for (const Observation& o : state->detector->Detect(*image, &r->counts)) {
    r->frame.point_ids.push_back(o.point_id);
    r->frame.points_in_parent.push_back(parent_from_points * scene.points[o.point_id]);
    r->frame.pixels.push_back(o.pixel);
    Eigen::Vector2d exact, centre;
    const int first_corner = o.point_id - o.point_id % 4;  // Tags own 4 consecutive points.
    const Eigen::Vector3d centre_in_points =
        (scene.points[first_corner] + scene.points[first_corner + 2]) / 2;
    if (ProjectPoint(intrinsics, cam_from_points * scene.points[o.point_id], &exact) &&
        ProjectPoint(intrinsics, cam_from_points * centre_in_points, &centre)) {
      r->errors.push_back(o.pixel - exact);
      r->outward.push_back((exact - centre).normalized());
      r->crlb_px.push_back(o.crlb_px);
    }
  }
}

}  // namespace

std::unique_ptr<RenderedSource> RenderedSource::Create(const SceneTruth& scene,
                                                       const std::vector<AprilGrid>& grids,
                                                       const RenderedSourceOptions& options,
                                                       uint64_t trial_seed, std::string* why) {
  if (!options.Check(why) || !scene.Check(why)) return nullptr;
  // Validates the target (one family, distinct ids) before any work; the calling thread's worker
  // then uses it.
  std::unique_ptr<FrameDetector> first_detector =
      FrameDetector::Create(grids, options.detection, why);
  if (!first_detector) return nullptr;
  std::vector<Eigen::Vector3d> corners;
  for (const AprilGrid& grid : grids) {
    const std::vector<Eigen::Vector3d> c = grid.CornersInPointsFrame();
    corners.insert(corners.end(), c.begin(), c.end());
  }
  if (corners.size() != scene.points.size()) {
    if (why) *why = "the scene's points are not the grids' corners";
    return nullptr;
  }
  const auto renderer = SceneRenderer::Create(scene, grids, options.render, why);
  if (!renderer) return nullptr;

  std::unique_ptr<RenderedSource> source(new RenderedSource());
  source->scene_ = scene;
  source->breakpoints_ = FrameTimes(options.frame_rate_hz, scene.duration_s);
  std::vector<FrameResult> results(source->breakpoints_.size());
  source->breakpoints_.push_back(scene.duration_s);

  // Per worker: a detector (worker 0 uses the one made above) and scratch buffers.
  std::vector<WorkerState> states(ParallelWorkers(options.threads, results.size()));
  states[0].detector = std::move(first_detector);
  ParallelFor(results.size(), options.threads, [&](int worker, size_t k) {
    WorkerState& state = states[worker];
    if (!state.detector) state.detector = FrameDetector::Create(grids, options.detection, nullptr);
    RenderAndDetect(scene, *renderer, {trial_seed, static_cast<int>(k), source->breakpoints_[k]},
                    &state, &results[k]);
  });

  DetectionStatsAccumulator stats;
  for (FrameResult& r : results) {
    if (!r.error.empty()) {
      if (why) *why = "frame at t = " + std::to_string(r.frame.time_s) + " s: " + r.error;
      return nullptr;
    }
    stats.AddFrame(r.tags_expected, r.counts, r.frame.pixels.empty());
    for (size_t i = 0; i < r.errors.size(); ++i)
      stats.AddCornerError(r.errors[i], r.outward[i], r.crlb_px[i]);
    source->frames_.push_back(std::move(r.frame));
  }
  source->stats_ = stats.Finish();
  return source;
}

}  // namespace calibench
