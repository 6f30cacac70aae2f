#include "bench/runner.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <mutex>
#include <thread>

#include "bench/methods.h"
#include "core/random.h"

namespace calibench {
namespace {

std::string Format(double v) {
  if (std::isnan(v)) return "nan";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.10g", v);
  return buf;
}

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
      {"detect_rate", Num(&RunRow::detect_rate)},
      {"corner_rms_px", Num(&RunRow::corner_rms_px)},
      {"frames_no_detection",
       [](const RunRow& r) { return std::to_string(r.frames_no_detection); }},
      {"measure_ms", Num(&RunRow::measure_ms)},
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

std::vector<RunRow> RunTrial(const ScenarioConfig& s, int trial, ScenarioShared* shared) {
  RunRow base;
  base.scenario = s.name;
  base.trial = trial;
  base.seed = TrialSeed(s.seed, static_cast<uint64_t>(trial));
  std::string why;
  const SceneTruth scene = s.MakeScene();
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<MeasurementSource> source;
  if (s.detections == "rendered") {
    auto rendered =
        RenderedSource::Create(scene, s.aprilgrids, s.RenderingOptions(), base.seed, &why);
    if (rendered) {
      const DetectionStats& stats = rendered->stats();
      base.detect_rate = stats.DetectionRate();
      base.corner_rms_px = stats.rms_px;
      base.frames_no_detection = stats.frames_without_detections;
    }
    source = std::move(rendered);
  } else {
    source = OracleSource::Create(scene, s.measurements, base.seed, &why);
  }
  base.measure_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (source) return RunMethods(s, scene, *source, base, shared);
  std::vector<RunRow> rows;
  for (const std::string& method : EnabledMethods(s)) {
    RunRow failed = base;
    failed.method = method;
    failed.status = "failed";
    failed.message = "measurements: " + why;
    rows.push_back(failed);
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
  std::vector<ScenarioShared> shared(scenarios.size());
  std::atomic<size_t> next{0};
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (size_t k = next++; k < tasks.size(); k = next++) {
      results[k] = RunTrial(scenarios[tasks[k].first], tasks[k].second, &shared[tasks[k].first]);
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
