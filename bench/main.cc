// calibench: the command-line entry point. Thin: parses arguments and calls the bench library.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

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
  CLI11_PARSE(app, argc, argv);
  try {
    if (run->parsed()) return Run(config_path, out_dir, threads, quiet);
  } catch (const std::exception& e) {  // A bug, not bad data: say so instead of aborting.
    std::cerr << "calibench: internal error: " << e.what() << "\n";
    return 70;
  }
  return 1;
}
