#include "bench/runner.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>

#include "adaptive/estimator.h"
#include "adaptive/theta.h"
#include "core/random.h"

namespace calibench {
namespace {

std::string Format(double v) {
  if (std::isnan(v)) return "nan";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.10g", v);
  return buf;
}

// Per-point RMS reprojection error of M_hat over all frames of the source.
double RmsReprojection(const MeasurementSource& source, const Matrix34d& m_hat) {
  Frame frame;
  double sum = 0.0;
  long count = 0;
  for (int k = 0; k < source.NumFrames(); ++k) {
    source.GetFrame(k, &frame);
    for (size_t i = 0; i < frame.pixels.size(); ++i) {
      const Eigen::Vector3d m = m_hat * frame.points_in_parent[i].homogeneous();
      sum += (m.hnormalized() - frame.pixels[i]).squaredNorm();
      ++count;
    }
  }
  return count ? std::sqrt(sum / count) : kUnset;
}

void FillCameraErrors(const ScenarioConfig& s, const RecoveredCamera& cam, RunRow* row) {
  const CameraIntrinsics& k = cam.intrinsics;
  row->fku = k.fku_px;
  row->fkv = k.fkv_px;
  row->phi_deg = k.phi_deg;
  row->u0 = k.u0_px;
  row->v0 = k.v0_px;
  const Eigen::Matrix3d& r_c = cam.parent_from_cam.rotation;
  // For an (opted-in) improper matrix the angles are those of -R_C, a proper rotation.
  const Eigen::Vector3d rpy = RollPitchYawDeg(cam.improper ? Eigen::Matrix3d(-r_c) : r_c);
  row->rc_roll_deg = rpy[0];
  row->rc_pitch_deg = rpy[1];
  row->rc_yaw_deg = rpy[2];
  const Eigen::Vector3d& x_c = cam.parent_from_cam.translation;
  row->xc_x = x_c[0];
  row->xc_y = x_c[1];
  row->xc_z = x_c[2];
  const CameraIntrinsics& t = s.truth.intrinsics;
  row->err_fku = k.fku_px - t.fku_px;
  row->err_fkv = k.fkv_px - t.fkv_px;
  row->err_phi_deg = k.phi_deg - t.phi_deg;
  row->err_u0 = k.u0_px - t.u0_px;
  row->err_v0 = k.v0_px - t.v0_px;
  row->rot_err_deg = RotationAngleDeg(r_c, s.truth.r_c);
  row->err_xc_norm = (x_c - s.truth.x_c).norm();
  row->ortho_defect = cam.orthogonality_defect;
  row->improper = cam.improper ? 1 : 0;
}

RunRow RunAdaptive(const ScenarioConfig& s, const MeasurementSource& source, RunRow row) {
  row.method = "adaptive";
  const Vector16d theta_true =
      ThetaFromCamera(s.truth.intrinsics, s.truth.ParentFromCam().Inverse());
  const CameraSpec& init = s.adaptive.initial;
  const Vector16d theta0 = ThetaFromCamera(init.intrinsics, init.ParentFromCam().Inverse());
  // Convergence time: the first recorded t after the last one with ||theta~|| >= tol.
  const double tol = s.adaptive.convergence_tol;
  double last_above = -1.0;
  double first_after = 0.0;
  bool pending = false;
  auto observer = [&](double t, const Vector16d& theta_hat) {
    if (ThetaError(theta_true, theta_hat) >= tol) {
      last_above = t;
      pending = true;
    } else if (pending) {
      first_after = t;
      pending = false;
    }
  };
  const AdaptiveSummary summary =
      RunAdaptiveEstimator(source, theta0, s.adaptive.options, observer);
  row.status = ToString(summary.status);
  row.message = summary.message;
  row.steps = summary.iterations;
  row.wall_ms = summary.wall_ms;
  row.theta_err_norm = ThetaError(theta_true, summary.theta_hat);
  if (!summary.IsUsable()) return row;
  row.converge_time_s = pending ? kUnset : (last_above < 0 ? 0.0 : first_after);
  row.pe_min_eig = PersistentExcitationIndex(summary.information, summary.theta_hat);
  row.rms_reproj_px = RmsReprojection(source, MFromTheta(summary.theta_hat));

  Frame last;
  source.Measure(source.Duration(), static_cast<int>(source.Breakpoints().size()) - 2, &last);
  RecoveredCamera cam;
  std::string why;
  if (!RecoverCamera(summary.theta_hat, last.points_in_parent, &cam, &why)) {
    row.status = "failed";
    row.message = "parameter recovery: " + why;
    return row;
  }
  FillCameraErrors(s, cam, &row);
  if (cam.improper && !s.truth.allow_improper_rotation) {
    row.message = "recovered rotation is improper (det < 0)";
  }
  return row;
}

}  // namespace

const std::vector<std::string>& RunRowHeader() {
  static const std::vector<std::string> header = {"scenario",
                                                  "trial",
                                                  "seed",
                                                  "method",
                                                  "status",
                                                  "fku",
                                                  "fkv",
                                                  "phi_deg",
                                                  "u0",
                                                  "v0",
                                                  "rc_roll_deg",
                                                  "rc_pitch_deg",
                                                  "rc_yaw_deg",
                                                  "xc_x",
                                                  "xc_y",
                                                  "xc_z",
                                                  "err_fku",
                                                  "err_fkv",
                                                  "err_phi_deg",
                                                  "err_u0",
                                                  "err_v0",
                                                  "rot_err_deg",
                                                  "err_xc_norm",
                                                  "theta_err_norm",
                                                  "rms_reproj_px",
                                                  "converge_time_s",
                                                  "pe_min_eig",
                                                  "ortho_defect",
                                                  "improper",
                                                  "steps",
                                                  "wall_ms",
                                                  "message"};
  return header;
}

std::vector<std::string> RunRowFields(const RunRow& r) {
  return {r.scenario,
          std::to_string(r.trial),
          std::to_string(r.seed),
          r.method,
          r.status,
          Format(r.fku),
          Format(r.fkv),
          Format(r.phi_deg),
          Format(r.u0),
          Format(r.v0),
          Format(r.rc_roll_deg),
          Format(r.rc_pitch_deg),
          Format(r.rc_yaw_deg),
          Format(r.xc_x),
          Format(r.xc_y),
          Format(r.xc_z),
          Format(r.err_fku),
          Format(r.err_fkv),
          Format(r.err_phi_deg),
          Format(r.err_u0),
          Format(r.err_v0),
          Format(r.rot_err_deg),
          Format(r.err_xc_norm),
          Format(r.theta_err_norm),
          Format(r.rms_reproj_px),
          Format(r.converge_time_s),
          Format(r.pe_min_eig),
          Format(r.ortho_defect),
          std::to_string(r.improper),
          std::to_string(r.steps),
          Format(r.wall_ms),
          r.message};
}

std::vector<RunRow> RunTrial(const ScenarioConfig& s, int trial) {
  RunRow base;
  base.scenario = s.name;
  base.trial = trial;
  base.seed = TrialSeed(s.seed, static_cast<uint64_t>(trial));
  std::vector<RunRow> rows;
  std::string why;
  const std::unique_ptr<OracleSource> source =
      OracleSource::Create(s.MakeScene(), s.measurements, base.seed, &why);
  if (s.adaptive.enabled) {
    if (!source) {
      RunRow failed = base;
      failed.method = "adaptive";
      failed.status = "failed";
      failed.message = "measurements: " + why;
      rows.push_back(failed);
    } else {
      rows.push_back(RunAdaptive(s, *source, base));
    }
  }
  return rows;
}

std::vector<RunRow> RunScenarios(const std::vector<ScenarioConfig>& scenarios,
                                 const RunOptions& options) {
  std::vector<std::pair<int, int>> tasks;  // (scenario, trial)
  for (size_t i = 0; i < scenarios.size(); ++i) {
    for (int t = 0; t < scenarios[i].trials; ++t) tasks.emplace_back(static_cast<int>(i), t);
  }
  std::vector<std::vector<RunRow>> results(tasks.size());
  std::atomic<size_t> next{0};
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (size_t k = next++; k < tasks.size(); k = next++) {
      results[k] = RunTrial(scenarios[tasks[k].first], tasks[k].second);
      const int finished = ++done;
      if (options.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        options.progress(finished, static_cast<int>(tasks.size()));
      }
    }
  };
  int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::max(1, std::min<int>(threads, static_cast<int>(tasks.size())));
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  std::vector<RunRow> rows;
  for (std::vector<RunRow>& r : results) {
    for (RunRow& row : r) rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace calibench
