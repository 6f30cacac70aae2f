// Runs scenarios: every (scenario, trial) builds its measurement source once from
// TrialSeed(seed, trial), runs every enabled method on it, and yields one RunRow per method.
// Trials run in parallel; rows come back in (scenario, trial, method) order whatever the thread
// count, and every number in them is independent of it.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "bench/scenario.h"

namespace calibench {

// One CSV row. Angles in degrees, pixels in px, lengths in the scene's unit (m). err_* are signed
// (estimate - truth); NaN where a figure does not apply or the method failed.
struct RunRow {
  std::string scenario;
  int trial = 0;
  uint64_t seed = 0;
  std::string method;
  std::string status;  // ok | diverged | failed
  std::string message;
  double fku = kUnset, fkv = kUnset, phi_deg = kUnset, u0 = kUnset, v0 = kUnset;
  double rc_roll_deg = kUnset, rc_pitch_deg = kUnset, rc_yaw_deg = kUnset;
  double xc_x = kUnset, xc_y = kUnset, xc_z = kUnset;
  double err_fku = kUnset, err_fkv = kUnset, err_phi_deg = kUnset, err_u0 = kUnset, err_v0 = kUnset;
  double rot_err_deg = kUnset, err_xc_norm = kUnset;
  double theta_err_norm = kUnset;
  double rms_reproj_px = kUnset;    // Per-point RMS (Euclidean), over all frames.
  double converge_time_s = kUnset;  // NaN: never stayed below the tolerance.
  double pe_min_eig = kUnset;       // PersistentExcitationIndex (adaptive only).
  double ortho_defect = kUnset;     // ||R^T R - I||_F of the recovered R before projection.
  // Reported standard deviations (ceres covariance) and the Cramer-Rao bound (sigma^2 (J^T J)^-1
  // at the truth; only with pixel noise alone, which is what it models).
  double std_fku = kUnset, std_fkv = kUnset, std_phi_deg = kUnset, std_u0 = kUnset, std_v0 = kUnset;
  double crlb_fku = kUnset, crlb_fkv = kUnset, crlb_phi_deg = kUnset, crlb_u0 = kUnset,
         crlb_v0 = kUnset;
  int improper = 0;  // 1 when the recovered rotation is a reflection.
  long steps = 0;    // Integrator steps / solver iterations.
  double wall_ms = kUnset;
  // detections: rendered (the same for every method of a trial; NaN / -1 for oracle).
  double detect_rate = kUnset;    // Tags detected / tags fully in the image.
  double corner_rms_px = kUnset;  // Detected corners vs exact projections.
  int frames_no_detection = -1;
  double measure_ms = kUnset;  // Wall time spent producing the measurements (render + detect).
};

const std::vector<std::string>& RunRowHeader();
std::vector<std::string> RunRowFields(const RunRow& row);

// Results the trials of one scenario share, computed once by whichever trial needs them first.
// They depend on the scenario alone, so their values do not depend on which trial or thread
// computes them (the rows stay identical for any thread count).
struct ScenarioShared {
  std::once_flag crlb_once;
  bool crlb_valid = false;
  std::array<double, 5> crlb_std{};  // fku, fkv, phi_deg (NaN without skew), u0, v0.
};

// Runs one trial of one scenario; never throws for bad data (a failed row instead). `shared`
// (optional) lets the scenario's trials share per-scenario work.
std::vector<RunRow> RunTrial(const ScenarioConfig& scenario, int trial,
                             ScenarioShared* shared = nullptr);

struct RunOptions {
  int threads = 0;  // 0: all cores.
  // Called after each finished trial with (done, total); from the worker threads, serialised.
  std::function<void(int done, int total)> progress;
};

std::vector<RunRow> RunScenarios(const std::vector<ScenarioConfig>& scenarios,
                                 const RunOptions& options);

}  // namespace calibench
