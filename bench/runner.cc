#include "bench/runner.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
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

Vector16d TrueTheta(const ScenarioConfig& s) {
  return ThetaFromCamera(s.truth.intrinsics, s.truth.ParentFromCam().Inverse());
}

RunRow RunAdaptive(const ScenarioConfig& s, const MeasurementSource& source, RunRow row) {
  row.method = "adaptive";
  const Vector16d theta_true = TrueTheta(s);
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

// The source's frames as views of the parent frame (what the batch methods see).
std::vector<View> FramesAsViews(const MeasurementSource& source) {
  std::vector<View> views(source.NumFrames());
  Frame frame;
  for (int k = 0; k < source.NumFrames(); ++k) {
    source.GetFrame(k, &frame);
    views[k].points = frame.points_in_parent;
    views[k].pixels = frame.pixels;
  }
  return views;
}

RunRow RunDlt(const ScenarioConfig& s, const std::vector<View>& views, RunRow row,
              DltResult* result) {
  row.method = "dlt";
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  for (const View& v : views) {
    points.insert(points.end(), v.points.begin(), v.points.end());
    pixels.insert(pixels.end(), v.pixels.begin(), v.pixels.end());
  }
  *result = EstimateDlt(points, pixels, s.dlt.options);
  row.status = ToString(result->status);
  row.message = result->message;
  row.wall_ms = result->wall_ms;
  row.steps = result->iterations;
  if (!result->IsUsable()) return row;
  row.theta_err_norm = ThetaError(TrueTheta(s), ThetaFromM(result->m));
  row.rms_reproj_px = result->rms_reproj_px;
  FillCameraErrors(s, result->camera, &row);
  return row;
}

// Cramer-Rao bound of the scenario's intrinsics for its pixel noise (NaN without pixel noise, or
// with noise on the 3D points, which the bound does not model).
void FillCrlb(const ScenarioConfig& s, const std::vector<View>& views, RunRow* row) {
  const NoiseOptions& noise = s.measurements.noise;
  if (!(noise.pixel_sigma_px > 0) || noise.point_sigma_m > 0) return;
  IntrinsicsCovariance cov;
  if (!IntrinsicsCovarianceAt(views, s.truth.intrinsics, {s.truth.ParentFromCam().Inverse()},
                              s.ceres.options, noise.pixel_sigma_px, &cov, nullptr)) {
    return;
  }
  const double deg = 180.0 / M_PI;
  row->crlb_fku = std::sqrt(cov(0, 0));
  row->crlb_fkv = std::sqrt(cov(1, 1));
  if (s.ceres.options.estimate_skew) row->crlb_phi_deg = std::sqrt(cov(2, 2)) * deg;
  row->crlb_u0 = std::sqrt(cov(3, 3));
  row->crlb_v0 = std::sqrt(cov(4, 4));
}

RunRow RunCeres(const ScenarioConfig& s, const std::vector<View>& views, const DltResult& dlt,
                RunRow row) {
  row.method = "ceres";
  if (!dlt.IsUsable()) {
    row.status = "failed";
    row.message = "initialisation (dlt) failed: " + dlt.message;
    return row;
  }
  const RefineResult r = RefineCalibration(views, dlt.camera.intrinsics,
                                           {dlt.camera.parent_from_cam.Inverse()}, s.ceres.options);
  row.status = ToString(r.status);
  row.message = r.message;
  row.wall_ms = r.wall_ms;
  row.steps = r.iterations;
  FillCrlb(s, views, &row);
  if (!r.IsUsable()) return row;
  DecomposedCamera cam;
  cam.intrinsics = r.intrinsics;
  cam.parent_from_cam = r.cam_from_object[0].Inverse();
  FillCameraErrors(s, cam, &row);
  CameraIntrinsics pinhole = r.intrinsics;
  pinhole.k1 = pinhole.k2 = pinhole.p1 = pinhole.p2 = pinhole.k3 = 0;
  row.theta_err_norm = ThetaError(TrueTheta(s), ThetaFromCamera(pinhole, r.cam_from_object[0]));
  row.rms_reproj_px = r.rms_reproj_px;
  const double deg = 180.0 / M_PI;
  row.std_fku = r.intrinsics_std[0];
  row.std_fkv = r.intrinsics_std[1];
  row.std_phi_deg = r.intrinsics_std[2] * deg;
  row.std_u0 = r.intrinsics_std[3];
  row.std_v0 = r.intrinsics_std[4];
  return row;
}

}  // namespace

namespace {

using Column = std::pair<std::string, std::function<std::string(const RunRow&)>>;

std::function<std::string(const RunRow&)> Num(double RunRow::*field) {
  return [field](const RunRow& r) { return Format(r.*field); };
}

// The CSV schema, in order: one entry per column.
const std::vector<Column>& Columns() {
  static const std::vector<Column> columns = {
      {"scenario", [](const RunRow& r) { return r.scenario; }},
      {"trial", [](const RunRow& r) { return std::to_string(r.trial); }},
      {"seed", [](const RunRow& r) { return std::to_string(r.seed); }},
      {"method", [](const RunRow& r) { return r.method; }},
      {"status", [](const RunRow& r) { return r.status; }},
      {"fku", Num(&RunRow::fku)},
      {"fkv", Num(&RunRow::fkv)},
      {"phi_deg", Num(&RunRow::phi_deg)},
      {"u0", Num(&RunRow::u0)},
      {"v0", Num(&RunRow::v0)},
      {"rc_roll_deg", Num(&RunRow::rc_roll_deg)},
      {"rc_pitch_deg", Num(&RunRow::rc_pitch_deg)},
      {"rc_yaw_deg", Num(&RunRow::rc_yaw_deg)},
      {"xc_x", Num(&RunRow::xc_x)},
      {"xc_y", Num(&RunRow::xc_y)},
      {"xc_z", Num(&RunRow::xc_z)},
      {"err_fku", Num(&RunRow::err_fku)},
      {"err_fkv", Num(&RunRow::err_fkv)},
      {"err_phi_deg", Num(&RunRow::err_phi_deg)},
      {"err_u0", Num(&RunRow::err_u0)},
      {"err_v0", Num(&RunRow::err_v0)},
      {"rot_err_deg", Num(&RunRow::rot_err_deg)},
      {"err_xc_norm", Num(&RunRow::err_xc_norm)},
      {"theta_err_norm", Num(&RunRow::theta_err_norm)},
      {"rms_reproj_px", Num(&RunRow::rms_reproj_px)},
      {"converge_time_s", Num(&RunRow::converge_time_s)},
      {"pe_min_eig", Num(&RunRow::pe_min_eig)},
      {"ortho_defect", Num(&RunRow::ortho_defect)},
      {"std_fku", Num(&RunRow::std_fku)},
      {"std_fkv", Num(&RunRow::std_fkv)},
      {"std_phi_deg", Num(&RunRow::std_phi_deg)},
      {"std_u0", Num(&RunRow::std_u0)},
      {"std_v0", Num(&RunRow::std_v0)},
      {"crlb_fku", Num(&RunRow::crlb_fku)},
      {"crlb_fkv", Num(&RunRow::crlb_fkv)},
      {"crlb_phi_deg", Num(&RunRow::crlb_phi_deg)},
      {"crlb_u0", Num(&RunRow::crlb_u0)},
      {"crlb_v0", Num(&RunRow::crlb_v0)},
      {"improper", [](const RunRow& r) { return std::to_string(r.improper); }},
      {"steps", [](const RunRow& r) { return std::to_string(r.steps); }},
      {"wall_ms", Num(&RunRow::wall_ms)},
      {"message", [](const RunRow& r) { return r.message; }},
  };
  return columns;
}

}  // namespace

const std::vector<std::string>& RunRowHeader() {
  static const std::vector<std::string> header = [] {
    std::vector<std::string> names;
    for (const Column& c : Columns()) names.push_back(c.first);
    return names;
  }();
  return header;
}

std::vector<std::string> RunRowFields(const RunRow& r) {
  std::vector<std::string> fields;
  fields.reserve(Columns().size());
  for (const Column& c : Columns()) fields.push_back(c.second(r));
  return fields;
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
  if (!source) {
    for (const char* method : {"adaptive", "dlt", "ceres"}) {
      const bool enabled = std::string(method) == "adaptive" ? s.adaptive.enabled
                           : std::string(method) == "dlt"    ? s.dlt.enabled
                                                             : s.ceres.enabled;
      if (!enabled) continue;
      RunRow failed = base;
      failed.method = method;
      failed.status = "failed";
      failed.message = "measurements: " + why;
      rows.push_back(failed);
    }
    return rows;
  }
  if (s.adaptive.enabled) rows.push_back(RunAdaptive(s, *source, base));
  if (s.dlt.enabled || s.ceres.enabled) {
    const std::vector<View> views = FramesAsViews(*source);
    DltResult dlt;
    RunRow dlt_row = RunDlt(s, views, base, &dlt);
    if (s.dlt.enabled) rows.push_back(dlt_row);
    if (s.ceres.enabled) rows.push_back(RunCeres(s, views, dlt, base));
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
