// Online mode of the batch methods (dlt, zhang, zhang_handeye, ceres): what a practitioner runs to
// follow a calibration that changes (spec dynamic-calibration.md, "What practitioners run
// instead"). Every every_s seconds of the trial the method is solved on the frames of the last
// window_s seconds, (t - window_s, t], warm-started from its previous solution where it can be;
// each estimate is reported to the sink at its solve time and holds until the next one.
//   window_s = 0     static: one solve on the whole trial (the default; the rows of a static
//                    scenario are those of the methods before online mode existed);
//   window_s > 0     a sliding window: memory = window, cost per solve ~ window;
//   window_s = all   the growing window (every frame so far): a static calibration repeated
//                    online, which cannot forget.
// The method's row is its last solve (at the end of the trial); wall time and iterations are the
// sums over all solves.
#pragma once

#include <functional>
#include <limits>
#include <string>

#include "methods/method.h"

namespace calibench {

struct OnlineOptions {
  double window_s = 0.0;  // 0: static; > 0: window length (s); infinity (`all`): growing.
  double every_s = 1.0;   // Solve period (s), in online mode.

  bool Online() const { return window_s > 0; }
  void Visit(OptionVisitor* v) {
    v->FieldOrAll({"window_s", "s",
                   "Online mode: solve on the frames of the last window_s seconds; 0: static "
                   "(one solve on the whole trial); `all`: the growing window."},
                  &window_s);
    v->Field({"every_s", "s", "Online mode: time between solves."}, &every_s);
  }
  bool Check(std::string* why) const;
};

// Solves on `window` (its Frames() are the window's), from `warm` (the previous usable estimate)
// when not null.
using WindowSolve =
    std::function<MethodResult(const MethodInput& window, const CameraEstimate* warm)>;

// Static mode: solve(input, nullptr). Online mode: the loop above.
MethodResult RunMaybeOnline(const MethodInput& input, const OnlineOptions& options,
                            EstimateSink* sink, const WindowSolve& solve);

}  // namespace calibench
