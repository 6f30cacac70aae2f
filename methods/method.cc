#include "methods/method.h"

#include <algorithm>
#include <cmath>

#include "util/format.h"

namespace calibench {

bool RefuseWideLens(const MethodInput& input, const std::string& method, MethodResult* result) {
  if (!InfoOf(input.lens).sees_past_90) return false;
  result->status = MethodStatus::kFailed;
  result->message = method + " assumes a pinhole projection; the camera's lens is " +
                    ToString(input.lens) +
                    " (rays past 90 deg): refused (zhang and ceres with model " +
                    ToString(input.lens) + " calibrate it)";
  return true;
}

FrameSet ReadFrames(const MeasurementSource& source) {
  FrameSet frames;
  frames.views.resize(source.NumFrames());
  frames.times_s.resize(source.NumFrames());
  frames.point_ids.resize(source.NumFrames());
  Frame frame;
  for (int k = 0; k < source.NumFrames(); ++k) {
    source.GetFrame(k, &frame);
    for (size_t i = 0; i < frame.pixels.size(); ++i) {
      frames.point_ids[k].push_back(frame.PointId(i));
    }
    frames.views[k].points = std::move(frame.points_in_parent);
    frames.views[k].pixels = std::move(frame.pixels);
    frames.times_s[k] = frame.time_s;
  }
  return frames;
}

void CountDataUsed(const FrameSet& frames, long* frames_used, long* observations_used) {
  *frames_used = 0;
  *observations_used = 0;
  for (const View& view : frames.views) {
    if (view.pixels.empty()) continue;
    ++*frames_used;
    *observations_used += static_cast<long>(view.pixels.size());
  }
}

const FrameSet& MethodInput::Frames() const {
  if (window_frames) return *window_frames;
  return cache->Get<FrameSet>("frames", [this] { return ReadFrames(*source); });
}

MethodInput MethodInput::Window(double from_s, double to_s) const {
  MethodInput window = *this;
  window.window_from_s = std::max(from_s, window_from_s);
  window.window_to_s = std::min(to_s, window_to_s);
  window.report_times_s.clear();
  // Held by the window alone: a sliding window's frames are freed with it.
  const FrameSet& all = Frames();
  auto frames = std::make_shared<FrameSet>();
  for (size_t k = 0; k < all.times_s.size(); ++k) {
    if (all.times_s[k] < window.window_from_s || all.times_s[k] > window.window_to_s) continue;
    frames->views.push_back(all.views[k]);
    frames->times_s.push_back(all.times_s[k]);
    frames->point_ids.push_back(all.point_ids[k]);
  }
  window.window_frames = std::move(frames);
  return window;
}

std::string MethodInput::WindowKey() const {
  if (std::isinf(window_from_s) && std::isinf(window_to_s)) return "";
  return "[" + FormatNumber(window_from_s, 17) + "," + FormatNumber(window_to_s, 17) + "]";
}

}  // namespace calibench
