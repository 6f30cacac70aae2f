#include "sim/measurements.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "util/random.h"

namespace calibench {

std::vector<double> FrameTimes(double rate_hz, double duration_s) {
  std::vector<double> times;
  const long count = static_cast<long>(std::ceil(duration_s * rate_hz - 1e-9));
  times.reserve(count);
  for (long k = 0; k < count; ++k) times.push_back(static_cast<double>(k) / rate_hz);
  return times;
}

bool NoiseOptions::Check(std::string* why) const {
  std::ostringstream msg;
  if (!(point_sigma_m >= 0 && std::isfinite(point_sigma_m))) {
    msg << "point_sigma_m must be >= 0, got " << point_sigma_m;
  } else if (!(pixel_sigma_px >= 0 && std::isfinite(pixel_sigma_px))) {
    msg << "pixel_sigma_px must be >= 0, got " << pixel_sigma_px;
  } else if (!(hold_s > 0 && std::isfinite(hold_s))) {
    msg << "hold_s must be > 0, got " << hold_s;
  } else if (hold_frames < 0) {
    msg << "hold_frames must be >= 0 (0: one draw for the whole run), got " << hold_frames;
  } else if (!(outlier_fraction >= 0 && outlier_fraction <= 1)) {
    msg << "outlier_fraction must lie in [0, 1], got " << outlier_fraction;
  } else if (!(outlier_sigma_px > 0 && std::isfinite(outlier_sigma_px))) {
    msg << "outlier_sigma_px must be > 0, got " << outlier_sigma_px;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

bool OracleOptions::Check(std::string* why) const {
  std::ostringstream msg;
  if (!(sample_rate_hz >= 0 && std::isfinite(sample_rate_hz))) {
    msg << "sample_rate_hz must be >= 0 (0 = continuous), got " << sample_rate_hz;
  } else if (!(eval_rate_hz > 0 && std::isfinite(eval_rate_hz))) {
    msg << "eval_rate_hz must be > 0, got " << eval_rate_hz;
  } else if (require_in_image_width < 0 || require_in_image_height < 0 ||
             (require_in_image_width > 0) != (require_in_image_height > 0)) {
    msg << "the required image size must be both positive or both 0, got " << require_in_image_width
        << " x " << require_in_image_height;
  } else if (!noise.Check(why)) {
    return false;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

OracleSource::OracleSource(const SceneTruth& scene, const OracleOptions& options)
    : scene_(scene), options_(options) {}

std::unique_ptr<OracleSource> OracleSource::Create(const SceneTruth& scene,
                                                   const OracleOptions& options,
                                                   uint64_t trial_seed, std::string* why) {
  if (!options.Check(why) || !scene.Check(why)) return nullptr;
  std::unique_ptr<OracleSource> source(new OracleSource(scene, options));
  const double duration = scene.duration_s;
  const bool sampled = options.sample_rate_hz > 0;
  if (sampled) {
    source->breakpoints_ = FrameTimes(options.sample_rate_hz, duration);
    source->frame_times_ = source->breakpoints_;
  } else {
    source->breakpoints_ = options.noise.Active() ? FrameTimes(1.0 / options.noise.hold_s, duration)
                                                  : std::vector<double>{0};
    source->frame_times_ = FrameTimes(options.eval_rate_hz, duration);
    // A step of the calibration is a jump of the measurements; a ramp's ends are kinks.
    const std::vector<double> changes = scene.ChangeTimes();
    if (!changes.empty()) {
      std::vector<double>& b = source->breakpoints_;
      b.insert(b.end(), changes.begin(), changes.end());
      std::sort(b.begin(), b.end());
      b.erase(std::unique(b.begin(), b.end()), b.end());
    }
  }
  source->breakpoints_.push_back(duration);

  // Every point must stay in front of the camera: at each frame and on a fine grid in between.
  std::vector<double> checks = source->frame_times_;
  for (int k = 0; k <= 2000; ++k) checks.push_back(duration * k / 2000.0);
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  const int width = options.require_in_image_width, height = options.require_in_image_height;
  for (double t : checks) {
    if (!scene.Observe(t, &points, &pixels, why)) return nullptr;
    if (width <= 0) continue;
    for (size_t i = 0; i < pixels.size(); ++i) {
      const Eigen::Vector2d& p = pixels[i];
      if (p.x() >= -0.5 && p.y() >= -0.5 && p.x() <= width - 0.5 && p.y() <= height - 0.5) {
        continue;
      }
      if (why) {
        std::ostringstream msg;
        msg << "feature point " << i << " projects outside the " << width << " x " << height
            << " image at t = " << t << " s (pixel " << p.x() << ", " << p.y()
            << "); a camera could not see it (measurements.outside_image: keep measures it "
               "anyway)";
        *why = msg.str();
      }
      return nullptr;
    }
  }

  if (options.noise.Active()) {
    const int segments = static_cast<int>(source->breakpoints_.size()) - 1;
    const int hold = options.noise.hold_frames;
    const int draws = !sampled ? segments : (hold == 0 ? 1 : (segments + hold - 1) / hold);
    const int n = static_cast<int>(scene.points.size());
    Rng point_rng(trial_seed, RngStream::kPointNoise);
    Rng pixel_rng(trial_seed, RngStream::kPixelNoise);
    source->point_noise_.resize(draws);
    source->pixel_noise_.resize(draws);
    for (int s = 0; s < draws; ++s) {
      Eigen::VectorXd& pn = source->point_noise_[s];
      Eigen::VectorXd& qn = source->pixel_noise_[s];
      pn.resize(3 * n);
      qn.resize(2 * n);
      for (int j = 0; j < 3 * n; ++j) pn[j] = options.noise.point_sigma_m * point_rng.Normal();
      for (int j = 0; j < 2 * n; ++j) qn[j] = options.noise.pixel_sigma_px * pixel_rng.Normal();
    }
    if (options.noise.outlier_fraction > 0) {
      Rng outlier_rng(trial_seed, RngStream::kOutliers);
      for (Eigen::VectorXd& qn : source->pixel_noise_) {
        for (int i = 0; i < n; ++i) {
          if (outlier_rng.Uniform() >= options.noise.outlier_fraction) continue;
          qn[2 * i] += options.noise.outlier_sigma_px * outlier_rng.Normal();
          qn[2 * i + 1] += options.noise.outlier_sigma_px * outlier_rng.Normal();
        }
      }
    }
  }
  return source;
}

void OracleSource::AddNoise(int segment, Frame* frame) const {
  if (point_noise_.empty()) return;
  const int hold = options_.noise.hold_frames;
  const int draw = options_.sample_rate_hz > 0 ? (hold == 0 ? 0 : segment / hold) : segment;
  const Eigen::VectorXd& pn = point_noise_[draw];
  const Eigen::VectorXd& qn = pixel_noise_[draw];
  for (size_t i = 0; i < frame->pixels.size(); ++i) {
    frame->points_in_parent[i] += pn.segment<3>(3 * i);
    frame->pixels[i] += qn.segment<2>(2 * i);
  }
}

void OracleSource::Measure(double t, int segment, Frame* frame) const {
  // A sampled source holds the frame captured at the segment's start.
  frame->time_s = options_.sample_rate_hz > 0 ? breakpoints_[segment] : t;
  double observed_at = frame->time_s;
  if (scene_.HasChanges() && options_.sample_rate_hz == 0 &&
      segment + 1 < static_cast<int>(breakpoints_.size()) && t >= breakpoints_[segment + 1]) {
    // The segment's end belongs to the segment: a step there takes effect in the next one.
    observed_at = std::nextafter(breakpoints_[segment + 1], -1.0);
  }
  // Create() verified every point is in front of the camera over the whole duration.
  scene_.Observe(observed_at, &frame->points_in_parent, &frame->pixels, nullptr);
  AddNoise(segment, frame);
}

int OracleSource::SegmentOf(double t) const {
  const auto it = std::upper_bound(breakpoints_.begin(), breakpoints_.end(), t);
  const int s = static_cast<int>(it - breakpoints_.begin()) - 1;
  return std::clamp(s, 0, static_cast<int>(breakpoints_.size()) - 2);
}

void OracleSource::GetFrame(int k, Frame* frame) const {
  const double t = frame_times_[k];
  Measure(t, SegmentOf(t), frame);
}

}  // namespace calibench
