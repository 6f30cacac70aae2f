// RenderedSource: the measurement source of `detections: rendered` — the whole chain a real camera
// runs. For each frame time t_k = k / frame_rate_hz (k = 0, 1, ... while t_k < duration):
//   1. place every AprilGrid in the camera: cam_from_board = CamFromParent * ParentFromPoints(t_k)
//      * points_from_board (scene.h, target.h);
//   2. render the 8-bit frame (sim/scene_renderer.h) with pixel noise drawn from (trial seed, k);
//   3. detect, refine and match the tags (frame_detector.h): the frame holds the detected points
//      x_bar_i(t_k) (exact 3D positions: the target is known) and their detected pixels.
// Measurements are held from t_k until t_k+1, as OracleSource's sampled mode does, so the two are
// interchangeable for every method. Frames are produced at creation, in parallel when asked; each
// frame depends only on (trial seed, k), so the result does not depend on the thread count.
// Frames without any detection are kept (empty) and counted, never fatal.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "detect/frame_detector.h"
#include "sim/measurements.h"
#include "sim/render.h"
#include "sim/scene.h"
#include "sim/scene_renderer.h"
#include "sim/target.h"

namespace calibench {

struct RenderedSourceOptions {
  double frame_rate_hz = 30.0;
  RenderOptions render;  // width, height: the camera's image size.
  FrameDetectorOptions detection;
  int threads = 1;  // Frames produced in parallel; 0: all cores.
  bool Check(std::string* why) const;
};

// Corner errors against the exact projections of the detected points (camera.h convention).
struct DetectionStats {
  int frames = 0;
  int frames_without_detections = 0;
  long tags_expected = 0;  // Tags whose four corners project at least 2 px inside the image.
  long tags_detected = 0;
  long unknown_tags = 0;    // Decoded ids on no grid (false positives or another target).
  long unrefined_tags = 0;  // Edge fit refused: raw detector corners kept.
  long unrefined_copy_tags =
      0;                  // Edge fit refused on a tag found only in a modified copy: dropped.
  long refused_tags = 0;  // Photometric fit refused: tag dropped (by reason below).
  std::array<long, kNumFitFailures> refused_by_reason{};  // Indexed by FitFailure.
  long border_tags = 0;                                   // Dropped for touching the image border.
  long predicted_tags = 0;  // Of tags_detected: fitted where neighbours predicted them.
  long refitted_tags = 0;   // Of tags_detected: decoded, refused from AprilTag 3's corners, then
                            // fitted where neighbours predicted them (DetectionCounts).
  long refused_predictions = 0;  // Predicted tags whose fit was refused (dropped).
  long covered_tags = 0;         // Of tags_detected: fitted without pixels that disagree (covered).
  long corners = 0;
  double rms_px = 0, bias_x_px = 0, bias_y_px = 0, p95_px = 0;  // Per-corner Euclidean error.
  // Mean error along each tag's diagonal, outward from the tag's projected centre (> 0: tags
  // look larger), and perpendicular to it (+90 degrees in the image): the symmetric errors that a
  // mean over x and y cancels (detect/corner_bias.h). NaN when no corner had its tag's direction.
  double bias_radial_px = 0, bias_tangent_px = 0;
  // RMS over the corners of the photometric fit's Cramer-Rao std per axis (px): the floor the
  // corner errors are compared with (RMS per axis = rms_px / sqrt 2). NaN without that fit.
  double crlb_rms_px = std::numeric_limits<double>::quiet_NaN();
  double DetectionRate() const {
    return tags_expected > 0 ? static_cast<double>(tags_detected) / tags_expected : 0.0;
  }
};

// Builds DetectionStats frame by frame (used by RenderedSource and `calibench detect`).
class DetectionStatsAccumulator {
 public:
  void AddFrame(int tags_expected, const DetectionCounts& counts, bool no_detection);
  // `outward`: the unit vector from the tag's projected centre to the corner's exact projection.
  // crlb_px: the corner's Cramer-Rao std (Observation::crlb_px), NaN when unknown.
  void AddCornerError(const Eigen::Vector2d& detected_minus_exact, const Eigen::Vector2d& outward,
                      double crlb_px = std::numeric_limits<double>::quiet_NaN());
  DetectionStats Finish() const;

 private:
  DetectionStats stats_;
  Eigen::Vector2d sum_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d sum_radial_tangent_ = Eigen::Vector2d::Zero();
  double sum_sq_ = 0;
  double crlb_sq_sum_ = 0;
  long crlb_count_ = 0;
  std::vector<double> norms_;
};

// Per grid, per tag: whether all four corners project at least 2 px inside the image, on the
// side of the board that faces the camera (the tags a detector is expected to find).
std::vector<std::vector<bool>> TagsInView(const CameraIntrinsics& intrinsics,
                                          const std::vector<BoardView>& views, int width,
                                          int height);

class RenderedSource final : public MeasurementSource {
 public:
  // nullptr (and *why) for invalid options or scene, or a target the detector cannot attribute.
  static std::unique_ptr<RenderedSource> Create(const SceneTruth& scene,
                                                const std::vector<AprilGrid>& grids,
                                                const RenderedSourceOptions& options,
                                                uint64_t trial_seed, std::string* why);

  int NumPoints() const override { return static_cast<int>(scene_.points.size()); }
  double Duration() const override { return scene_.duration_s; }
  const std::vector<double>& Breakpoints() const override { return breakpoints_; }
  void Measure(double t, int segment, Frame* frame) const override { *frame = frames_[segment]; }
  bool HeldWithinSegments() const override { return true; }
  int NumFrames() const override { return static_cast<int>(frames_.size()); }
  void GetFrame(int k, Frame* frame) const override { *frame = frames_[k]; }
  const DetectionStats& stats() const { return stats_; }

 private:
  RenderedSource() = default;
  SceneTruth scene_;
  std::vector<double> breakpoints_;
  std::vector<Frame> frames_;
  DetectionStats stats_;
};

}  // namespace calibench
