// Measurement sources: what every estimator consumes. A source yields, for any time t, the known
// points x_bar_i (in the parent frame P, see scene.h) and their measured pixels p_i.
//
// Time is cut into segments [b_k, b_k+1] by Breakpoints() (b_0 = 0, b_K = duration). Inside a
// segment the measurements are smooth in t; they may jump at a breakpoint (a new camera frame, a
// new noise draw). Integrators restart at breakpoints and pass the segment index, because a stage
// evaluated exactly at b_k+1 still belongs to segment k.
//
// Discrete frames (NumFrames / GetFrame) are what a batch method sees and what the reprojection
// error is computed over: the camera frames of a sampled source, or a regular evaluation grid of a
// continuous one.
//
// OracleSource: exact projections of the scene plus the thesis noise model (Gaussian on x_bar and
// on p, drawn once per segment and held, as a sampled noise block does), either
//   continuous (sample_rate_hz = 0): x_bar(t), p(t) exact functions of t, the thesis's Simulink
//       model; noise (if any) is held for noise_hold_s; or
//   sampled (sample_rate_hz > 0): frames at k / rate, held constant until the next frame (what a
//       detector at a frame rate gives); noise is drawn per frame, or once per hold_frames frames
//       (hold_frames = 0: one draw for the whole run, a fixed error pattern per point, the way a
//       detector's systematic corner errors behave under slow motion).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/scene.h"

namespace calibench {

struct Frame {
  double time_s = 0.0;
  std::vector<Eigen::Vector3d> points_in_parent;  // x_bar_i (measured: may carry noise).
  std::vector<Eigen::Vector2d> pixels;            // p_i (measured: may carry noise).
  // Which scene point each entry is (a detector sees a subset); empty: all, in order.
  std::vector<int> point_ids;
  int PointId(size_t i) const { return point_ids.empty() ? static_cast<int>(i) : point_ids[i]; }
};

class MeasurementSource {
 public:
  virtual ~MeasurementSource() = default;
  virtual int NumPoints() const = 0;
  virtual double Duration() const = 0;
  // b_0 = 0 < b_1 < ... < b_K = Duration().
  virtual const std::vector<double>& Breakpoints() const = 0;
  // Measurements at time t in segment `segment` (b_segment <= t <= b_segment+1).
  virtual void Measure(double t, int segment, Frame* frame) const = 0;
  // True when Measure() depends on the segment only (held frames): callers may measure once per
  // segment.
  virtual bool HeldWithinSegments() const = 0;
  virtual int NumFrames() const = 0;
  virtual void GetFrame(int k, Frame* frame) const = 0;
};

// The regular grid 0, 1/rate, 2/rate, ... strictly below duration_s (frame times at a rate).
std::vector<double> FrameTimes(double rate_hz, double duration_s);

struct NoiseOptions {
  double point_sigma_m = 0.0;   // Std of the Gaussian added to each coordinate of x_bar.
  double pixel_sigma_px = 0.0;  // Std of the Gaussian added to u and v.
  // Continuous sources: each noise draw is held this long (Simulink's noise block default 0.1 s).
  double hold_s = 0.1;
  // Sampled sources: one draw per this many consecutive frames; 0: one draw for the whole run.
  int hold_frames = 1;
  // Gross outliers (Huber's contamination model): each pixel measurement of a draw is, with
  // probability outlier_fraction, displaced by a further Gaussian of std outlier_sigma_px per axis
  // (a mismatched feature). Drawn from their own stream: the other noise does not change with them.
  double outlier_fraction = 0.0;
  double outlier_sigma_px = 20.0;
  bool Check(std::string* why) const;
  bool Active() const {  // Random noise.
    return point_sigma_m > 0 || pixel_sigma_px > 0 || outlier_fraction > 0;
  }
};

struct OracleOptions {
  double sample_rate_hz = 0.0;  // 0: continuous measurements; > 0: frames held between samples.
  double eval_rate_hz = 10.0;   // Continuous sources: frame grid for batch methods and metrics.
  NoiseOptions noise;
  // > 0: every exact projection must fall inside the image, [-0.5, width - 0.5] x
  // [-0.5, height - 0.5] (pixel centres at integers), or Create() refuses the scene: a camera
  // could not see the point. 0: no bound (the thesis's model, where every point is measured).
  int require_in_image_width = 0, require_in_image_height = 0;
  bool Check(std::string* why) const;
};

class OracleSource final : public MeasurementSource {
 public:
  // Returns nullptr and says why when the options are invalid or a point is behind the camera (or
  // outside a required image) at any frame time or at any of 2000 instants over the duration.
  static std::unique_ptr<OracleSource> Create(const SceneTruth& scene, const OracleOptions& options,
                                              uint64_t trial_seed, std::string* why);

  int NumPoints() const override { return static_cast<int>(scene_.points.size()); }
  double Duration() const override { return scene_.duration_s; }
  const std::vector<double>& Breakpoints() const override { return breakpoints_; }
  void Measure(double t, int segment, Frame* frame) const override;
  bool HeldWithinSegments() const override { return options_.sample_rate_hz > 0; }
  int NumFrames() const override { return static_cast<int>(frame_times_.size()); }
  void GetFrame(int k, Frame* frame) const override;

 private:
  OracleSource(const SceneTruth& scene, const OracleOptions& options);
  void AddNoise(int segment, Frame* frame) const;
  int SegmentOf(double t) const;

  SceneTruth scene_;
  OracleOptions options_;
  std::vector<double> breakpoints_;
  std::vector<double> frame_times_;
  // Per segment: point noise (3 per point) and pixel noise (2 per point), if noise is active.
  std::vector<Eigen::VectorXd> point_noise_, pixel_noise_;
};

}  // namespace calibench
