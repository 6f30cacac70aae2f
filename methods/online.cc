#include "methods/online.h"

#include <cmath>
#include <sstream>

namespace calibench {

bool OnlineOptions::Check(std::string* why) const {
  std::ostringstream msg;
  if (!(window_s >= 0)) {
    msg << "window_s must be >= 0 (0: static) or all, got " << window_s;
  } else if (Online() && !(every_s > 0 && std::isfinite(every_s))) {
    msg << "every_s must be a positive number of seconds, got " << every_s;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

MethodResult RunMaybeOnline(const MethodInput& input, const OnlineOptions& options,
                            EstimateSink* sink, const WindowSolve& solve) {
  if (!options.Online()) return solve(input, nullptr);
  const double duration = input.source->Duration();
  std::vector<double> times;
  for (long k = 1; k * options.every_s <= duration + 1e-9; ++k)
    times.push_back(k * options.every_s);
  if (times.empty() || times.back() < duration - 1e-9) times.push_back(duration);
  MethodResult last, result;
  bool have_estimate = false;
  CameraEstimate warm;
  int solves = 0, failed = 0;
  double wall_ms = 0.0;
  long iterations = 0;
  for (double t : times) {
    const double from = std::isinf(options.window_s) ? -1.0 : t - options.window_s;
    // (from, t]: a frame exactly at the window's start belongs to the previous window.
    const MethodInput window =
        input.Window(std::nextafter(from, std::numeric_limits<double>::infinity()), t);
    last = solve(window, have_estimate ? &warm : nullptr);
    ++solves;
    wall_ms += last.wall_ms;
    iterations += last.iterations;
    if (!last.IsUsable() || !last.estimate.has_camera) {
      ++failed;
      continue;
    }
    warm = last.estimate;
    have_estimate = true;
    result = last;
    // The row reports the data of the estimate it holds: the last window's.
    if (result.frames_used < 0)
      CountDataUsed(window.Frames(), &result.frames_used, &result.observations_used);
    if (sink != nullptr) sink->OnEstimate(t, last.estimate);
  }
  if (!have_estimate) result = last;  // Every solve failed: the last one's reason.
  std::ostringstream note;
  note << "online: " << solves << " solves";
  if (failed > 0) note << " (" << failed << " failed)";
  note << ", window "
       << (std::isinf(options.window_s) ? std::string("all")
                                        : std::to_string(options.window_s) + " s")
       << " every " << options.every_s << " s";
  if (!last.IsUsable() && have_estimate) note << "; the last solve failed: " << last.message;
  if (!result.message.empty()) note << "; " << result.message;
  result.message = note.str();
  result.wall_ms = wall_ms;
  result.iterations = iterations;
  return result;
}

}  // namespace calibench
