// calibench: the command-line entry point. Thin: parses arguments and calls the bench library.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "bench/calibrate.h"
#include "bench/config_io.h"
#include "bench/csv.h"
#include "bench/runner.h"
#include "bench/table.h"

namespace {

void ProgressBar(int done, int total) {
  const int width = 40;
  const int filled = total ? width * done / total : width;
  std::fprintf(stderr, "\r[%s%s] %d/%d trials", std::string(filled, '#').c_str(),
               std::string(width - filled, '.').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

int Run(const std::string& config_path, const std::string& out_dir, int threads, bool quiet) {
  calibench::RunConfig config;
  std::string why;
  if (!calibench::LoadRunConfig(config_path, &config, &why)) {
    std::cerr << "calibench: invalid configuration: " << why << "\n";
    return 2;
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    std::cerr << "calibench: " << out_dir
              << ": cannot create the output directory: " << ec.message() << "\n";
    return 3;
  }
  for (const calibench::ScenarioConfig& s : config.scenarios) {
    if (s.truth.allow_improper_rotation) {
      std::cerr << "calibench: warning: scenario '" << s.name
                << "': truth R_C is allowed to be improper (det = -1), to reproduce a source "
                   "that printed such a matrix; no real camera has one\n";
    }
  }
  const std::string resolved_path = out_dir + "/config.resolved.yaml";
  if (!calibench::WriteFileAtomically(resolved_path, calibench::ResolvedYaml(config), &why)) {
    std::cerr << "calibench: " << why << "\n";
    return 3;
  }
  calibench::RunOptions options;
  options.threads = threads;
  if (!quiet && ::isatty(STDERR_FILENO)) options.progress = ProgressBar;
  const std::vector<calibench::RunRow> rows = calibench::RunScenarios(config.scenarios, options);

  std::string csv = calibench::CsvLine(calibench::RunRowHeader());
  for (const calibench::RunRow& row : rows) csv += calibench::CsvLine(calibench::RunRowFields(row));
  const std::string table = calibench::ThesisTable(config.scenarios, rows);
  if (!calibench::WriteFileAtomically(out_dir + "/runs.csv", csv, &why) ||
      !calibench::WriteFileAtomically(out_dir + "/table.md", table, &why)) {
    std::cerr << "calibench: " << why << "\n";
    return 3;
  }
  if (!quiet) std::cout << table;
  std::cerr << "calibench: wrote " << rows.size() << " rows to " << out_dir << "/runs.csv\n";
  return 0;
}

int Calibrate(const std::string& points_path, const std::string& out_path,
              const std::string& model_name, bool skew) {
  calibench::CalibrateOptions options;
  if (!calibench::ParseLensModel(model_name, &options.model)) {
    std::cerr << "calibench: --model: unknown lens model '" << model_name
              << "' (pinhole, pinhole-k2, pinhole-radtan4, pinhole-radtan5)\n";
    return 2;
  }
  options.estimate_skew = skew;
  calibench::PointData data;
  std::string why;
  if (!calibench::LoadPointData(points_path, &data, &why)) {
    std::cerr << "calibench: --points: " << why << "\n";
    return 2;
  }
  const calibench::CalibrateReport report = calibench::CalibrateFromPoints(data, options);
  std::cout << calibench::FormatCalibrateReport(report, data);
  if (!report.IsUsable()) return 4;
  if (!calibench::WriteCameraYaml(out_path, report.camera, &why)) {
    std::cerr << "calibench: " << why << "\n";
    return 3;
  }
  std::cerr << "calibench: wrote " << out_path << "\n";
  return 0;
}

}  // namespace

// CLI11 throws from setup only on a programming error (a duplicate option name).
int main(int argc, char** argv) {  // NOLINT(bugprone-exception-escape)
  CLI::App app{"calibench: adaptive vs batch camera calibration, on identical data"};
  app.require_subcommand(1);
  std::string config_path, out_dir;
  int threads = 0;
  bool quiet = false;
  CLI::App* run = app.add_subcommand("run", "Run the scenarios of a YAML config");
  run->add_option("config", config_path, "Scenario file or entry point (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--out", out_dir, "Output directory (runs.csv, config.resolved.yaml, table.md)")
      ->required();
  run->add_option("--threads", threads, "Worker threads (0: all cores)")
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--quiet", quiet, "No table on stdout, no progress bar");
  std::string points_path, camera_out = "camera.yaml", model = "pinhole-k2";
  bool skew = false;
  CLI::App* calibrate = app.add_subcommand("calibrate", "Calibrate a camera from point files");
  calibrate
      ->add_option("--points", points_path, "Zhang folder (Model.txt, data*.txt) or OpenCV .dat")
      ->required();
  calibrate->add_option("--out", camera_out, "Output camera.yaml (OpenCV FileStorage)");
  calibrate->add_option("--model", model,
                        "Lens model: pinhole, pinhole-k2, pinhole-radtan4, pinhole-radtan5");
  calibrate->add_flag("--skew", skew, "Estimate the skew angle phi too");
  CLI11_PARSE(app, argc, argv);
  try {
    if (run->parsed()) return Run(config_path, out_dir, threads, quiet);
    if (calibrate->parsed()) return Calibrate(points_path, camera_out, model, skew);
  } catch (const std::exception& e) {  // A bug, not bad data: say so instead of aborting.
    std::cerr << "calibench: internal error: " << e.what() << "\n";
    return 70;
  }
  return 1;
}
