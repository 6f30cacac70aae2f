// Dynamic calibration through the harness: a short load step on the dynamic rig. Every
// tracking method reports a trajectory and per-event figures; the sliding window re-converges
// within its window and period while the growing window does not; the tracking files are
// byte-identical for 1 and 2 threads and across shards.
#include <gtest/gtest.h>

#include "bench/config/config_io.h"
#include "bench/run/run_dir.h"
#include "bench/run/runner.h"
#include "tests/common/temp_files.h"

namespace calibench {
namespace {

const std::string kShort = std::string(CALIBENCH_SOURCE_DIR) + "/tests/bench/dynamic/short.yaml";

RunConfig LoadShort() {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfig(kShort, &config, &why)) << why;
  return config;
}

const EventMetrics* Find(const RunRow& row, int event, const std::string& quantity) {
  for (const EventMetrics& e : row.events) {
    if (e.event == event && TrackQuantityNames()[e.quantity] == quantity) return &e;
  }
  return nullptr;
}

TEST(Dynamic, MethodsTrackAPitchStep) {
  const RunConfig config = LoadShort();
  ASSERT_EQ(config.scenarios.size(), 1u);
  const ScenarioConfig& s = config.scenarios[0];
  EXPECT_TRUE(s.Tracks());
  const std::vector<RunRow> rows = RunTrial(s, 0);
  ASSERT_EQ(rows.size(), 4u);
  for (const RunRow& r : rows) {
    ASSERT_EQ(r.status, "ok") << r.method << ": " << r.message;
    // One sample per frame (10 Hz x 20 s); 2 events (start, step) x 7 quantities.
    ASSERT_EQ(r.track.size(), 200u) << r.method;
    EXPECT_EQ(r.events.size(), 14u) << r.method;
    // The truth in the track is the stepped camera after 10 s: camera 1's R_C = Rz(180) Rx(90),
    // so a pitch of +0.5 deg about the body's y axis is -0.5 deg of R_C's own Euler pitch.
    EXPECT_NEAR(r.track[50].truth[1], 0.0, 1e-9);
    EXPECT_NEAR(r.track[150].truth[1], -0.5, 1e-9);
  }
  const RunRow &adaptive = rows[0], &ekf = rows[1], &window = rows[2], &growing = rows[3];
  // The sliding window: once the window holds only frames after the step (2 s) and a solve has
  // run (every 0.5 s), its pitch is the new one: within 2.5 s + one frame.
  const EventMetrics* w = Find(window, 1, "pitch_deg");
  ASSERT_NE(w, nullptr);
  EXPECT_LE(w->reconverge_s, 2.6);
  EXPECT_LT(w->steady_err, 0.02);
  // The growing window averages the 10 s before the step with the 10 s after: never within.
  const EventMetrics* g = Find(growing, 1, "pitch_deg");
  ASSERT_NE(g, nullptr);
  EXPECT_TRUE(std::isnan(g->reconverge_s)) << g->reconverge_s;
  EXPECT_GT(g->steady_err, 0.1);
  // The thesis's estimator at t0 = 10 s, alpha = 1000 (time constant ~ t0 / alpha = 10 ms) and
  // the EKF both follow it within a few frames.
  for (const RunRow* r : {&adaptive, &ekf}) {
    const EventMetrics* e = Find(*r, 1, "pitch_deg");
    ASSERT_NE(e, nullptr);
    EXPECT_LE(e->reconverge_s, 1.0) << r->method;
    EXPECT_GE(e->peak_err, 0.3) << r->method;  // It saw the step.
  }
  // The EKF reports its covariance: NEES at every sample after its start.
  EXPECT_TRUE(std::isfinite(ekf.track.back().nees));
  EXPECT_TRUE(std::isnan(adaptive.track.back().nees));
}

std::string TempDir(const std::string& name) { return FreshTempDir("calibench_dynamic_", name); }

TEST(Dynamic, TrackingFilesDoNotDependOnThreadsOrShards) {
  const RunConfig config = LoadShort();
  RunDirOptions one, two;
  one.out_dir = TempDir("t1");
  one.threads = 1;
  two.out_dir = TempDir("t2");
  two.threads = 2;
  ASSERT_TRUE(RunToDirectory(config, one).ok);
  ASSERT_TRUE(RunToDirectory(config, two).ok);
  std::vector<std::string> shards;
  for (int k = 1; k <= 2; ++k) {
    RunDirOptions o;
    o.out_dir = TempDir("shard" + std::to_string(k));
    o.shard.index = k;
    o.shard.count = 2;
    ASSERT_TRUE(RunToDirectory(config, o).ok);
    shards.push_back(o.out_dir);
  }
  std::string why;
  const std::string merged = TempDir("merged");
  ASSERT_TRUE(MergeRunDirectories({shards[1], shards[0]}, merged, &why)) << why;
  for (const char* file : {"runs.csv", "events.csv", "tracks.csv", "track_errors.csv",
                           "track_bands.csv", "summary.csv"}) {
    const std::string a = Slurp(one.out_dir + "/" + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(Slurp(two.out_dir + "/" + file), a) << file << ": 1 vs 2 threads";
    EXPECT_EQ(Slurp(merged + "/" + file), a) << file << ": 2 shards merged";
  }
  // events.csv: 2 trials x 4 methods x 2 events x 7 quantities; tracks.csv: trial 0 only.
  const std::string events = Slurp(one.out_dir + "/events.csv");
  EXPECT_EQ(std::count(events.begin(), events.end(), '\n'), 1 + 2 * 4 * 2 * 7);
  const std::string tracks = Slurp(one.out_dir + "/tracks.csv");
  EXPECT_EQ(std::count(tracks.begin(), tracks.end(), '\n'), 1 + 4 * 200);
}

}  // namespace
}  // namespace calibench
