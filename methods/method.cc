#include "methods/method.h"

namespace calibench {

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

const FrameSet& MethodInput::Frames() const {
  return cache->Get<FrameSet>("frames", [this] { return ReadFrames(*source); });
}

}  // namespace calibench
