// methods/online.h: the online mode of the batch methods, with a stub solve that records what it is
// given. The solve times and windows for window_s / every_s are checked against the rule written
// out by hand (every_s multiples in (0, T], then T), each window's frames against the trial's
// frames filtered independently by (t - window_s, t], and the warm start, the sink's report times,
// failed solves and the summed figures against the stub's own record.
#include "methods/online.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/synthetic.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

class Recorder final : public EstimateSink {
 public:
  void OnSeries(double, const std::string&, const Eigen::VectorXd&) override {}
  void OnEstimate(double t, const CameraEstimate& e) override {
    times.push_back(t);
    tags.push_back(e.intrinsics.fku_px);
  }
  std::vector<double> times, tags;
};

// What the stub saw on one call.
struct Call {
  double from = 0, to = 0;
  std::vector<double> frame_times;
  double warm_tag = -1;  // The warm estimate's tag, -1 without one.
};

// A solve that records its call, tags its estimate with its call number (in f*ku) and fails the
// calls listed in `fail`.
WindowSolve Stub(std::vector<Call>* calls, const std::vector<int>& fail = {}) {
  return [calls, fail](const MethodInput& window, const CameraEstimate* warm) {
    const int number = static_cast<int>(calls->size()) + 1;
    calls->push_back({window.window_from_s, window.window_to_s, window.Frames().times_s,
                      warm != nullptr ? warm->intrinsics.fku_px : -1.0});
    MethodResult r;
    r.iterations = 10 * number;
    r.wall_ms = number;
    if (std::find(fail.begin(), fail.end(), number) != fail.end()) {
      r.status = MethodStatus::kFailed;
      r.message = "stub failure " + std::to_string(number);
      return r;
    }
    r.status = MethodStatus::kOk;
    r.message = "stub " + std::to_string(number);
    r.estimate.has_camera = true;
    r.estimate.intrinsics.fku_px = number;
    return r;
  };
}

// The rig for T = 10 s at 10 frames/s (frames at k / 10 s).
std::unique_ptr<SyntheticTrial> TenSeconds() {
  const BoardRigScene rig = SwayingBoardRig();
  SceneTruth scene = rig.scene;
  scene.duration_s = 10;
  OracleOptions o;
  o.sample_rate_hz = 10;
  return SyntheticTrial::Create(scene, o, 1, rig.layouts);
}

// The trial's frame times in (from, to], filtered here (not through MethodInput::Window).
std::vector<double> FramesIn(const SyntheticTrial& trial, double from, double to) {
  std::vector<double> out;
  for (double t : trial.input.Frames().times_s) {
    if (t > from && t <= to) out.push_back(t);
  }
  return out;
}

// window_s 2, every_s 3 on T = 10: solves at 3, 6, 9 and at the end 10, on (1, 3], (4, 6], (7, 9],
// (8, 10]. Times and window bounds are sums and differences of small integers: exact in double.
TEST(RunMaybeOnline, SlidingWindowsEveryPeriodAndAtTheEnd) {
  auto trial = TenSeconds();
  ASSERT_NE(trial, nullptr);
  ASSERT_EQ(trial->input.source->Duration(), 10.0);
  OnlineOptions options;
  options.window_s = 2, options.every_s = 3;
  std::vector<Call> calls;
  Recorder sink;
  const MethodResult r = RunMaybeOnline(trial->input, options, &sink, Stub(&calls));
  const std::vector<double> expected_times = {3, 6, 9, 10};
  ASSERT_EQ(calls.size(), expected_times.size());
  EXPECT_EQ(sink.times, expected_times);
  for (size_t i = 0; i < calls.size(); ++i) {
    const double t = expected_times[i];
    EXPECT_EQ(calls[i].to, t) << i;
    // The window opens just after t - window_s: a frame exactly there belongs to the previous one.
    EXPECT_GT(calls[i].from, t - 2) << i;
    EXPECT_EQ(calls[i].from, std::nextafter(t - 2, 100.0)) << i;
    EXPECT_EQ(calls[i].frame_times, FramesIn(*trial, t - 2, t)) << i;
    // A 2 s window at 10 frames/s holds 20 frames, 19 or 21 at a boundary that rounding moves.
    EXPECT_NEAR(static_cast<double>(calls[i].frame_times.size()), 20, 1) << i;
    EXPECT_EQ(calls[i].warm_tag, i == 0 ? -1.0 : static_cast<double>(i)) << i;  // The previous.
  }
  // The row is the last solve's; iterations and wall time are summed over the four.
  EXPECT_TRUE(r.IsUsable());
  EXPECT_EQ(r.estimate.intrinsics.fku_px, 4);
  EXPECT_EQ(r.iterations, 10 + 20 + 30 + 40);
  EXPECT_EQ(r.wall_ms, 1 + 2 + 3 + 4);
  EXPECT_EQ(r.frames_used, static_cast<long>(calls.back().frame_times.size()));
  EXPECT_NE(r.message.find("online: 4 solves, window 2"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("every 3 s; stub 4"), std::string::npos) << r.message;
  // Mutation checked: windows [t - w, t] (online.cc without nextafter) and a warm start kept at the
  // first estimate both fail here.
}

// every_s dividing T: no extra solve at the end; window_s = all: every frame up to t.
TEST(RunMaybeOnline, GrowingWindowWithAPeriodThatDividesTheTrial) {
  auto trial = TenSeconds();
  ASSERT_NE(trial, nullptr);
  OnlineOptions options;
  options.window_s = std::numeric_limits<double>::infinity(), options.every_s = 2.5;
  std::vector<Call> calls;
  Recorder sink;
  const MethodResult r = RunMaybeOnline(trial->input, options, &sink, Stub(&calls));
  const std::vector<double> expected_times = {2.5, 5, 7.5, 10};
  EXPECT_EQ(sink.times, expected_times);
  ASSERT_EQ(calls.size(), expected_times.size());
  for (size_t i = 0; i < calls.size(); ++i) {
    EXPECT_EQ(calls[i].to, expected_times[i]);
    EXPECT_EQ(calls[i].frame_times, FramesIn(*trial, -1e300, expected_times[i])) << i;
  }
  EXPECT_EQ(calls.back().frame_times, trial->input.Frames().times_s);  // All of them at the end.
  EXPECT_NE(r.message.find("window all every 2.5 s"), std::string::npos) << r.message;
  // Mutation checked: appending T when times.back() <= T (a second solve at 10) fails here.
}

// A failed solve reports nothing, is counted, and does not replace the warm start.
TEST(RunMaybeOnline, FailedSolvesAreSkippedAndCounted) {
  auto trial = TenSeconds();
  ASSERT_NE(trial, nullptr);
  OnlineOptions options;
  options.window_s = 4, options.every_s = 4;  // Solves at 4, 8, 10.
  std::vector<Call> calls;
  Recorder sink;
  const MethodResult r = RunMaybeOnline(trial->input, options, &sink, Stub(&calls, {2}));
  ASSERT_EQ(calls.size(), 3u);
  EXPECT_EQ(sink.times, (std::vector<double>{4, 10}));
  EXPECT_EQ(sink.tags, (std::vector<double>{1, 3}));
  EXPECT_EQ(calls[2].warm_tag, 1.0);  // Call 1's estimate: call 2 failed.
  EXPECT_EQ(r.estimate.intrinsics.fku_px, 3);
  EXPECT_NE(r.message.find("3 solves (1 failed)"), std::string::npos) << r.message;
  // Every solve failing: the last one's reason, failed.
  calls.clear();
  const MethodResult none = RunMaybeOnline(trial->input, options, nullptr, Stub(&calls, {1, 2, 3}));
  EXPECT_FALSE(none.IsUsable());
  EXPECT_NE(none.message.find("stub failure 3"), std::string::npos) << none.message;
}

// window_s = 0: one solve on the whole trial, no warm start, nothing reported.
TEST(RunMaybeOnline, StaticModeSolvesOnceOnTheWholeTrial) {
  auto trial = TenSeconds();
  ASSERT_NE(trial, nullptr);
  std::vector<Call> calls;
  Recorder sink;
  const MethodResult r = RunMaybeOnline(trial->input, OnlineOptions{}, &sink, Stub(&calls));
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_TRUE(std::isinf(calls[0].from) && std::isinf(calls[0].to));
  EXPECT_EQ(calls[0].frame_times, trial->input.Frames().times_s);
  EXPECT_EQ(calls[0].warm_tag, -1.0);
  EXPECT_TRUE(sink.times.empty());
  EXPECT_EQ(r.message, "stub 1");
}

TEST(OnlineOptions, AreChecked) {
  std::string why;
  OnlineOptions o;
  EXPECT_TRUE(o.Check(&why));  // Static: every_s is not used.
  o.window_s = -1;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("window_s must be >= 0"), std::string::npos) << why;
  o.window_s = 5, o.every_s = 0;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("every_s must be a positive"), std::string::npos) << why;
  o.every_s = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(o.Check(&why));
}

}  // namespace
}  // namespace calibench
