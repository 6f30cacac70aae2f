// Rig scenarios in the harness (bench/config/scenario.h `rig:`, bench/run/trial.h): the `rig:`
// block reads back what it writes and refuses each bad rig naming file, line and field; a rig
// trial's camera 0 rows are the single-camera scenario's rows; the rig metrics
// (metrics/rig_metrics.h) against closed forms; a camera-1 knock is seen in rig.csv; the joint
// method ekf_rig runs on every camera's input at once and its rows carry its relative pose; the
// files do not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>

#include "bench/config/config_io.h"
#include "bench/run/run_dir.h"
#include "bench/run/runner.h"
#include "metrics/rig_metrics.h"
#include "tests/common/temp_files.h"

namespace calibench {
namespace {

const std::string kDir = std::string(CALIBENCH_SOURCE_DIR) + "/tests/bench/";
const std::string kShortRig = kDir + "rig/short_rig.yaml";
const std::string kShort = kDir + "dynamic/short.yaml";

RunConfig Load(const std::string& path) {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfig(path, &config, &why)) << why;
  return config;
}

constexpr double kDeg = M_PI / 180.0;

TEST(Rig, ParsesAndReadsBackWhatItWrites) {
  const RunConfig config = Load(kShortRig);
  ASSERT_EQ(config.scenarios.size(), 1u);
  const ScenarioConfig& s = config.scenarios[0];
  ASSERT_EQ(s.NumCameras(), 2);
  EXPECT_EQ(s.CameraName(0), "left");
  EXPECT_EQ(s.CameraName(1), "right");
  EXPECT_EQ(s.ChangeCamera(0), -1);
  EXPECT_EQ(s.ChangeCamera(1), 1);
  const RigCameraConfig& right = s.rig.cameras[1];
  EXPECT_EQ(right.intrinsics.fku_px, 815);
  EXPECT_EQ(right.t_m, Eigen::Vector3d(-0.12, 0, 0));
  // Exactly the rotation the rpy gives (camera/pose.h).
  EXPECT_EQ(right.r, FromRollPitchYawDeg(Eigen::Vector3d(0.4, -0.3, 0.2)));
  // Camera 1 in the parent frame: parent_from_cam_0 * cam_from_rig_1^-1 (scenario.h).
  const ScenarioConfig cam1 = s.CameraScenario(1);
  const Rigid3 expected = s.truth.ParentFromCam() * right.CamFromRig().Inverse();
  EXPECT_TRUE(cam1.truth.r_c.isApprox(expected.rotation, 1e-15));
  EXPECT_TRUE(cam1.truth.x_c.isApprox(expected.translation, 1e-15));
  EXPECT_EQ(cam1.truth.intrinsics.fku_px, 815);
  EXPECT_EQ(cam1.truth_changes.size(), 2u);                 // The whole rig's and its own.
  EXPECT_EQ(s.CameraScenario(0).truth_changes.size(), 1u);  // The whole rig's.
  // The resolved YAML reads back to an equal scenario, rig and change cameras included.
  const std::string yaml = ResolvedYaml(config);
  EXPECT_NE(yaml.find("rig:"), std::string::npos);
  RunConfig back;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(yaml, "resolved.yaml", &back, &why)) << why;
  ASSERT_EQ(back.scenarios.size(), 1u);
  EXPECT_TRUE(back.scenarios[0] == s);
  EXPECT_EQ(back.scenarios[0].ChangeCamera(1), 1);
  EXPECT_EQ(ResolvedYaml(back), yaml);
  // A scenario without rig writes no rig and no change camera.
  const std::string single = ResolvedYaml(Load(kShort));
  EXPECT_EQ(single.find("rig:"), std::string::npos);
  EXPECT_EQ(single.find("camera:"), std::string::npos);
}

TEST(Rig, RotationAsAMatrixReadsBack) {
  const std::string yaml =
      "base: " + kShortRig +
      "\nscenario:\n"
      "  rig:\n"
      "    cameras:\n"
      "      - {name: left}\n"
      "      - name: right\n"
      "        intrinsics: {fku_px: 815, fkv_px: 806, phi_deg: 90, u0_px: 318, v0_px: 242}\n"
      "        cam_from_rig: {R: [[1, 0, 0], [0, 0.9998476951563913, -0.01745240643728351],\n"
      "                          [0, 0.01745240643728351, 0.9998476951563913]], t_m: [-0.12, 0, "
      "0]}\n";
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(yaml, kDir + "rig/matrix.yaml", &config, &why)) << why;
  const RigCameraConfig& right = config.scenarios[0].rig.cameras[1];
  EXPECT_TRUE(right.rotation_as_matrix);
  EXPECT_NEAR(LogSO3(right.r)[0], 1.0 * kDeg, 1e-12);
  RunConfig back;
  ASSERT_TRUE(LoadRunConfigFromString(ResolvedYaml(config), "resolved.yaml", &back, &why)) << why;
  EXPECT_TRUE(back.scenarios[0] == config.scenarios[0]);
  EXPECT_EQ(back.scenarios[0].rig.cameras[1].r, right.r);
}

// The error of short_rig.yaml with its `rig:` block replaced by `rig_yaml` (and `extra` lines in
// the scenario), as LoadRunConfigFromString words it.
std::string RigError(const std::string& rig_yaml, const std::string& extra = "") {
  const std::string yaml = "base: " + kShortRig + "\nscenario:\n" + extra + rig_yaml;
  RunConfig config;
  std::string why;
  EXPECT_FALSE(LoadRunConfigFromString(yaml, kDir + "rig/bad.yaml", &config, &why));
  return why;
}

const char* kRight =
    "      - name: right\n"
    "        intrinsics: {fku_px: 815, fkv_px: 806, phi_deg: 90, u0_px: 318, v0_px: 242}\n";

TEST(Rig, RefusesEachBadRigNamingFileLineAndField) {
  const std::string head = "  rig:\n    cameras:\n      - {name: left}\n";
  const std::string where = kDir + "rig/bad.yaml:";
  struct Case {
    std::string rig, extra, where, field, reason;
  };
  const std::vector<Case> cases = {
      {"  rig:\n    cameras:\n      - {name: left}\n", "", where + "5:", "rig.cameras",
       "at least 2 cameras, got 1"},
      {"  rig:\n    cameras:\n      - {name: left, cam_from_rig: {t_m: [0.1, 0, 0]}}\n" +
           std::string(kRight) + "        cam_from_rig: {t_m: [-0.12, 0, 0]}\n",
       "", where + "5:", "rig.cameras[0]", "must be the identity"},
      {"  rig:\n    cameras:\n      - name: left\n        intrinsics: {fku_px: 800, fkv_px: 800, "
       "u0_px: 320, v0_px: 240}\n" +
           std::string(kRight) + "        cam_from_rig: {t_m: [-0.12, 0, 0]}\n",
       "", where + "5:", "rig.cameras[0].intrinsics", "truth camera"},
      {head + kRight + "        cam_from_rig: {R: [[-1, 0, 0], [0, 1, 0], [0, 0, 1]]}\n", "",
       where + "8:", "rig.cameras[1].cam_from_rig", "improper"},
      {head + "      - {name: right}\n", "", where + "6:", "rig.cameras[1].intrinsics", "missing"},
      {head + "      - name: right\n        intrinsics: {fku_px: -5, fkv_px: 806, u0_px: 318, "
              "v0_px: 242}\n        cam_from_rig: {t_m: [-0.12, 0, 0]}\n",
       "", where + "7:", "rig.cameras[1].intrinsics", "fku"},
      {head + kRight + "        cam_from_rig: {t_m: [0, 0, 0]}\n", "",
       where + "6:", "rig.cameras[1].t_m", "centre"},
      // Turned around (yaw 180 deg about the rig's y axis): every point behind it.
      {head + kRight + "        cam_from_rig: {rpy_deg: [0, 180, 0], t_m: [-0.12, 0, 0]}\n", "",
       where + "6:", "rig.cameras[1]", "behind"},
      // Turned 60 deg away: the points project outside its image (outside_image: fail) ...
      {head + kRight + "        cam_from_rig: {rpy_deg: [0, 60, 0], t_m: [-0.12, 0, 0]}\n", "",
       where + "6:", "rig.cameras[1]", "outside its 640 x 480 image"},
      // ... and with outside_image: keep, it sees none of them.
      {head + kRight + "        cam_from_rig: {rpy_deg: [0, 60, 0], t_m: [-0.12, 0, 0]}\n",
       "  measurements: {outside_image: keep}\n", where + "7:", "rig.cameras[1]",
       "sees none of the 160 points"},
  };
  for (const Case& c : cases) {
    const std::string why = RigError(c.rig, c.extra);
    EXPECT_EQ(why.rfind(c.where, 0), 0u) << why << "\n(expected at " << c.where << ")";
    EXPECT_NE(why.find(c.field + ":"), std::string::npos) << why;
    EXPECT_NE(why.find(c.reason), std::string::npos) << why;
  }
  // A change naming a camera the rig lacks; a change camera without a rig.
  {
    const std::string yaml = "base: " + kShortRig +
                             "\nscenario:\n  truth:\n    changes:\n"
                             "      - {kind: step, at_s: 5, camera: 2, rpy_deg: [0.1, 0, 0]}\n";
    RunConfig config;
    std::string why;
    EXPECT_FALSE(LoadRunConfigFromString(yaml, kDir + "rig/bad.yaml", &config, &why));
    EXPECT_EQ(why.rfind(where + "5:", 0), 0u) << why;
    EXPECT_NE(why.find("truth.changes[0].camera: 2 names no camera"), std::string::npos) << why;
  }
  {
    const std::string yaml = "base: " + kShort +
                             "\nscenario:\n  truth:\n    changes:\n"
                             "      - {kind: step, at_s: 5, camera: 1, rpy_deg: [0.1, 0, 0]}\n";
    RunConfig config;
    std::string why;
    EXPECT_FALSE(LoadRunConfigFromString(yaml, kDir + "rig/bad.yaml", &config, &why));
    EXPECT_NE(why.find("has no `rig`"), std::string::npos) << why;
  }
}

TEST(Rig, CameraZeroRowsAreTheSingleCameraRows) {
  const ScenarioConfig rig = Load(kShortRig).scenarios[0];
  const ScenarioConfig single = Load(kShort).scenarios[0];
  for (int trial = 0; trial < 2; ++trial) {
    const std::vector<RunRow> rig_rows = RunTrial(rig, trial);
    const std::vector<RunRow> single_rows = RunTrial(single, trial);
    ASSERT_EQ(rig_rows.size(), 2 * single_rows.size());
    for (size_t i = 0; i < single_rows.size(); ++i) {
      const RunRow &a = rig_rows[i], &b = single_rows[i];
      EXPECT_EQ(a.camera, 0);
      EXPECT_EQ(RunRowFields(a), RunRowFields(b)) << b.method;
      EXPECT_EQ(EventLines(a), EventLines(b)) << b.method;
      EXPECT_EQ(TrackLines(a), TrackLines(b)) << b.method;
      EXPECT_FALSE(a.rig.has_value());
      const RunRow& c1 = rig_rows[single_rows.size() + i];
      EXPECT_EQ(c1.camera, 1);
      EXPECT_EQ(c1.method, b.method);
      EXPECT_EQ(c1.status, "ok") << c1.method << ": " << c1.message;
      EXPECT_NE(RunRowFields(c1), RunRowFields(b)) << "camera 1 has its own noise and camera";
      ASSERT_TRUE(c1.rig.has_value());
    }
  }
}

TEST(Rig, MetricsAgainstClosedForms) {
  Rigid3 truth;
  truth.translation = Eigen::Vector3d(-0.12, 0, 0);  // Camera 1 0.12 m to camera 0's right.
  RigErrorOptions options;
  options.focal_px = 800.0;
  // 0.2 deg about camera 1's x axis: the relative rotation's error, and on the plane the rays
  // of camera 1 turn by 0.2 deg in y: at the grid's centre (straight ahead) a vertical
  // disparity of exactly f tan(0.2 deg), elsewhere f tan(0.2 deg) (1 + (y/f)^2)-ish.
  Rigid3 est = truth;
  est.rotation = ExpSO3(Eigen::Vector3d(0.2 * kDeg, 0, 0));
  const RigErrors e = EvaluateRig(est, truth, options);
  EXPECT_NEAR(e.rel_rot_err_deg[0], 0.2, 1e-12);
  EXPECT_NEAR(e.rel_rot_err_deg[1], 0.0, 1e-12);
  EXPECT_NEAR(e.rel_rot_err_norm_deg, 0.2, 1e-12);
  EXPECT_NEAR(e.baseline_err_mm, 0.0, 1e-9);
  const double expected_px = 800.0 * std::tan(0.2 * kDeg);  // 2.79 px.
  const std::vector<double> v = PlaneVerticalDisparitiesPx(est, truth, options);
  ASSERT_EQ(v.size(), 25u);
  EXPECT_NEAR(std::abs(v[12]), expected_px, 1e-9);
  // Over +-15 deg down and +-20 deg across: between 1 and 1 / cos^2(15 deg) = 1.072 of it, and the
  // plane's parallax adds (0.12 m at 10 m) a little.
  EXPECT_GT(e.vdisp_rms_px, expected_px);
  EXPECT_LT(e.vdisp_rms_px, 1.08 * expected_px);
  EXPECT_NEAR(e.vdisp_max_px, expected_px / std::pow(std::cos(15 * kDeg), 2), 0.02);
  // A pitch error leaves the depth on the axis (the horizontal disparity) all but unchanged.
  EXPECT_LT(std::abs(e.depth_err_near_pct), 1e-3);
  // A baseline 1 mm long (exact rotation): every depth 1/120 too far, nothing vertical.
  Rigid3 longer = truth;
  longer.translation.x() = -0.121;
  const RigErrors b = EvaluateRig(longer, truth, options);
  EXPECT_NEAR(b.baseline_err_mm, 1.0, 1e-9);
  EXPECT_NEAR(b.depth_err_near_pct, 100.0 / 120.0, 1e-9);
  EXPECT_NEAR(b.depth_err_far_pct, 100.0 / 120.0, 1e-9);
  EXPECT_NEAR(b.vdisp_max_px, 0.0, 1e-9);
  EXPECT_NEAR(b.rel_rot_err_norm_deg, 0.0, 1e-12);
  // A yaw error d (about camera 1's y axis) shifts the horizontal disparity by about f tan(d):
  // Z_est = f B / (f B / Z + f tan d), so the depth error grows with Z (Algers 2018's point).
  Rigid3 yawed = truth;
  yawed.rotation = ExpSO3(Eigen::Vector3d(0, 0.01 * kDeg, 0));
  const RigErrors y = EvaluateRig(yawed, truth, options);
  const auto approx = [](double z) {
    const double d = 0.12 / z + std::tan(0.01 * kDeg);
    return 100.0 * ((0.12 / d) - z) / z;
  };
  EXPECT_NEAR(std::abs(y.depth_err_near_pct), std::abs(approx(10)), 0.02 * std::abs(approx(10)));
  EXPECT_NEAR(std::abs(y.depth_err_far_pct), std::abs(approx(30)), 0.02 * std::abs(approx(30)));
  EXPECT_GT(std::abs(y.depth_err_far_pct), 2.5 * std::abs(y.depth_err_near_pct));
}

TEST(Rig, SegmentFiguresAsTheEvents) {
  // Errors 1 before 2 s, then 0.05: re-converged 2 s after a segment starting at 0.
  std::vector<double> t, err;
  for (int i = 0; i < 100; ++i) {
    t.push_back(0.1 * i);
    err.push_back(i < 20 ? 1.0 : 0.05);
  }
  const SegmentFigures f = EvaluateSegment(t, err, 0.0, 10.0, 0.1, 0.2);
  EXPECT_NEAR(f.reconverge_s, 2.0, 1e-12);
  EXPECT_EQ(f.steady_err, 0.05);
  EXPECT_EQ(f.peak_err, 1.0);
  err.back() = 1.0;  // Outside at the end: never re-converged.
  EXPECT_TRUE(std::isnan(EvaluateSegment(t, err, 0.0, 10.0, 0.1, 0.2).reconverge_s));
}

TEST(Rig, KnockOfCameraOneIsSeenInTheRigRows) {
  const ScenarioConfig s = Load(kShortRig).scenarios[0];
  // The truth: camera 1's relative rotation turns by 0.3 deg at 15 s, not at 10 s (the whole
  // rig's pitch moves both cameras).
  const SceneTruth s0 = s.MakeCameraScene(0), s1 = s.MakeCameraScene(1);
  const auto rel = [&](double t) { return s1.CamFromParentAt(t) * s0.ParentFromCamAt(t); };
  EXPECT_NEAR(RotationAngleDeg(rel(0).rotation, rel(12).rotation), 0.0, 1e-12);
  EXPECT_NEAR(RotationAngleDeg(rel(12).rotation, rel(16).rotation), 0.3, 1e-12);
  // Turned about its own centre: its centre in the rig, -R^T t, stays.
  const auto centre = [&](double t) { return rel(t).Inverse().translation; };
  EXPECT_NEAR((centre(16) - centre(0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(centre(0).norm(), 0.12, 1e-12);
  EXPECT_NEAR(RotationAngleDeg(s0.ParentFromCamAt(0).rotation, s0.ParentFromCamAt(12).rotation),
              0.5, 1e-12);
  const std::vector<RunRow> rows = RunTrial(s, 0);
  for (const RunRow& r : rows) {
    if (r.camera != 1) continue;
    ASSERT_TRUE(r.rig.has_value());
    const RigRow& g = *r.rig;
    EXPECT_EQ(g.status, "ok") << r.method;
    EXPECT_EQ(g.segment_from_s, 15.0);
    EXPECT_EQ(g.rel_rot_tol_deg, 0.1);
    if (r.method == "ceres-w2" || r.method == "ekf") {
      // Both cameras' estimates follow within a few seconds (the sliding window: its 2 s window
      // and 0.5 s period): so does the relative rotation.
      EXPECT_LE(g.rel_rot.reconverge_s, 3.0) << r.method;
      EXPECT_LT(g.rel_rot.steady_err, 0.1) << r.method;
      EXPECT_LT(g.errors.rel_rot_err_norm_deg, 0.1) << r.method;
    }
    if (r.method == "ceres-all") {  // The growing window averages before and after the knock.
      EXPECT_TRUE(std::isnan(g.rel_rot.reconverge_s));
    }
    EXPECT_TRUE(std::isfinite(g.errors.vdisp_rms_px)) << r.method;
    EXPECT_TRUE(std::isfinite(g.errors.depth_err_far_pct)) << r.method;
  }
}

TEST(Rig, AKnockAloneTracksEveryCamera) {
  // Only camera 1 changes: camera 0's scenario has no change of its own, and still tracks.
  const std::string yaml = "base: " + kShortRig +
                           "\nscenario:\n  trials: 1\n  truth:\n    changes:\n"
                           "      - {kind: step, at_s: 15, camera: 1, rpy_deg: [0.3, 0, 0]}\n"
                           "  methods:\n    - {name: ekf, type: ekf, init: dlt, "
                           "pixel_sigma_px: 0.2}\n";
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(yaml, kDir + "rig/knock.yaml", &config, &why)) << why;
  const std::vector<RunRow> rows = RunTrial(config.scenarios[0], 0);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].track.size(), 200u);  // Camera 0: 10 frames/s x 20 s.
  EXPECT_EQ(rows[0].events.size(), 7u);   // Only the start (7 quantities).
  ASSERT_TRUE(rows[1].rig.has_value());
  EXPECT_EQ(rows[1].rig->segment_from_s, 15.0);
  EXPECT_LE(rows[1].rig->rel_rot.reconverge_s, 3.0);
}

// The joint rig EKF (methods/ekf_rig.h) beside the composed one: each camera's row is ok and
// camera 1's rig figures (its parent_from_cam against camera 0's: the filter's cam_1_from_cam_0)
// follow the knock as the composed filter's do (same bounds as above). A scenario without `rig:`
// gives it nothing to estimate jointly: a failed row naming why.
TEST(Rig, JointEkfRowsCarryItsRelativePose) {
  const std::string methods =
      "  methods:\n    - {name: ekf, type: ekf, init: dlt, pixel_sigma_px: 0.2}\n"
      "    - {name: ekf-rig, type: ekf_rig, init: dlt, pixel_sigma_px: 0.2}\n";
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString("base: " + kShortRig + "\nscenario:\n  trials: 1\n" + methods,
                                      kDir + "rig/joint.yaml", &config, &why))
      << why;
  const std::vector<RunRow> rows = RunTrial(config.scenarios[0], 0);
  ASSERT_EQ(rows.size(), 4u);  // Per camera: ekf, ekf-rig.
  for (const RunRow& r : rows) {
    EXPECT_EQ(r.status, "ok") << r.method << " camera " << r.camera << ": " << r.message;
    if (r.camera != 1) continue;
    ASSERT_TRUE(r.rig.has_value());
    EXPECT_EQ(r.rig->status, "ok") << r.method;
    EXPECT_LE(r.rig->rel_rot.reconverge_s, 3.0) << r.method;
    EXPECT_LT(r.rig->rel_rot.steady_err, 0.1) << r.method;
    EXPECT_LT(r.rig->errors.rel_rot_err_norm_deg, 0.1) << r.method;
  }
  EXPECT_NE(rows[1].message.find("2 cameras jointly"), std::string::npos) << rows[1].message;

  ASSERT_TRUE(LoadRunConfigFromString("base: " + kShort + "\nscenario:\n  trials: 1\n" + methods,
                                      kDir + "dynamic/joint.yaml", &config, &why))
      << why;
  const std::vector<RunRow> single = RunTrial(config.scenarios[0], 0);
  ASSERT_EQ(single.size(), 2u);
  EXPECT_EQ(single[0].status, "ok");
  EXPECT_EQ(single[1].status, "failed");
  EXPECT_NE(single[1].message.find("no `rig:` cameras"), std::string::npos) << single[1].message;
}

std::string TempDir(const std::string& name) { return FreshTempDir("calibench_rig_", name); }

TEST(Rig, FilesDoNotDependOnThreads) {
  const RunConfig config = Load(kShortRig);
  RunDirOptions one, two;
  one.out_dir = TempDir("t1");
  one.threads = 1;
  two.out_dir = TempDir("t2");
  two.threads = 2;
  ASSERT_TRUE(RunToDirectory(config, one).ok);
  ASSERT_TRUE(RunToDirectory(config, two).ok);
  for (const char* file : {"runs.csv", "rig.csv", "events.csv", "tracks.csv", "track_errors.csv",
                           "track_bands.csv", "summary.csv", "schema.json"}) {
    const std::string a = Slurp(one.out_dir + "/" + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(Slurp(two.out_dir + "/" + file), a) << file << ": 1 vs 2 threads";
  }
  // runs.csv: a camera column last; 2 trials x 4 methods x 2 cameras. rig.csv: 2 x 4 x camera 1.
  const std::string runs = Slurp(one.out_dir + "/runs.csv");
  EXPECT_NE(runs.substr(0, runs.find('\n')).rfind(",camera"), std::string::npos);
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 1 + 2 * 4 * 2);
  const std::string rig = Slurp(one.out_dir + "/rig.csv");
  EXPECT_EQ(std::count(rig.begin(), rig.end(), '\n'), 1 + 2 * 4);
  EXPECT_EQ(rig.rfind("scenario,sweep,point,params,trial,seed,method,camera,status,", 0), 0u);
  // summary.csv per camera: its header ends in camera.
  const std::string summary = Slurp(one.out_dir + "/summary.csv");
  EXPECT_EQ(summary.substr(0, summary.find('\n')).substr(summary.find('\n') - 7), ",camera");
  EXPECT_NE(Slurp(one.out_dir + "/schema.json").find("\"rig.csv\""), std::string::npos);
}

}  // namespace
}  // namespace calibench
