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
#include "bench/frames_io.h"
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

struct CalibrateArgs {
  std::string points_path, images_dir, target_path;
  std::string out_path = "camera.yaml", model = "pinhole-k2";
  bool skew = false;
};

int Calibrate(const CalibrateArgs& args) {
  const std::string& out_path = args.out_path;
  const std::string& model_name = args.model;
  const bool skew = args.skew;
  calibench::CalibrateOptions options;
  if (!calibench::ParseLensModel(model_name, &options.model)) {
    std::cerr << "calibench: --model: unknown lens model '" << model_name
              << "' (pinhole, pinhole-k2, pinhole-radtan4, pinhole-radtan5)\n";
    return 2;
  }
  options.estimate_skew = skew;
  calibench::PointData data;
  std::string why;
  calibench::ImageFolderReport images;
  std::vector<int> used_index;
  if (!args.images_dir.empty()) {
    calibench::CalibrationTarget target;
    if (args.target_path.empty()) {
      std::cerr << "calibench: --images needs --target TARGET.yaml (Kalibr aprilgrid or "
                   "checkerboard)\n";
      return 2;
    }
    if (!calibench::LoadTargetYaml(args.target_path, &target, &why)) {
      std::cerr << "calibench: --target: " << why << "\n";
      return 2;
    }
    if (!calibench::LoadImagePoints(args.images_dir, target, &data, &images, &used_index, &why)) {
      std::cerr << "calibench: --images: " << why << "\n";
      return 2;
    }
  } else if (!calibench::LoadPointData(args.points_path, &data, &why)) {
    std::cerr << "calibench: --points: " << why << "\n";
    return 2;
  }
  const calibench::CalibrateReport report = calibench::CalibrateFromPoints(data, options);
  std::cout << calibench::FormatCalibrateReport(report, data);
  if (!args.images_dir.empty()) {
    std::cout << calibench::FormatImageReport(images, used_index, report);
  }
  if (!report.IsUsable()) return 4;
  if (!calibench::WriteCameraYaml(out_path, report.camera, &why)) {
    std::cerr << "calibench: " << why << "\n";
    return 3;
  }
  std::cerr << "calibench: wrote " << out_path << "\n";
  return 0;
}

struct FramesArgs {
  std::string config_path, frames_dir, scenario;
  calibench::FramesOptions options;
};

// The scenario named `name` (or the config's first), or nullptr after saying why.
const calibench::ScenarioConfig* PickScenario(const calibench::RunConfig& config,
                                              const std::string& name) {
  for (const calibench::ScenarioConfig& s : config.scenarios) {
    if (name.empty() || s.name == name) return &s;
  }
  std::cerr << "calibench: --scenario: no scenario named '" << name << "'\n";
  return nullptr;
}

int RenderOrDetect(const FramesArgs& args, bool render) {
  calibench::RunConfig config;
  std::string why;
  if (!calibench::LoadRunConfig(args.config_path, &config, &why)) {
    std::cerr << "calibench: invalid configuration: " << why << "\n";
    return 2;
  }
  const calibench::ScenarioConfig* s = PickScenario(config, args.scenario);
  if (s == nullptr) return 2;
  if (render) {
    int frames = 0;
    if (!calibench::WriteRenderedFrames(*s, args.options, args.frames_dir, &frames, &why)) {
      std::cerr << "calibench: render: " << why << "\n";
      return 3;
    }
    std::cerr << "calibench: wrote " << frames << " frames and corners.csv to " << args.frames_dir
              << "\n";
    return 0;
  }
  calibench::DetectionStats stats;
  if (!calibench::DetectFrames(*s, args.options, args.frames_dir, &stats, &why)) {
    std::cerr << "calibench: detect: " << why << "\n";
    return 3;
  }
  std::cout << "scenario " << s->name << ", trial " << args.options.trial
            << (args.frames_dir.empty() ? " (rendered in memory)\n"
                                        : " (" + args.frames_dir + ")\n")
            << calibench::FormatDetectionStats(stats);
  return 0;
}

void AddFramesOptions(CLI::App* command, FramesArgs* args) {
  command->add_option("config", args->config_path, "Scenario file (YAML) with aprilgrids")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--scenario", args->scenario, "Scenario name (default: the first)");
  command->add_option("--trial", args->options.trial, "Trial index (noise seed)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--max-frames", args->options.max_frames, "At most this many frames")
      ->check(CLI::NonNegativeNumber);
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
  CalibrateArgs cal;
  CLI::App* calibrate =
      app.add_subcommand("calibrate", "Calibrate a camera from point files or from images");
  CLI::Option* points_option = calibrate->add_option(
      "--points", cal.points_path, "Zhang folder (Model.txt, data*.txt) or OpenCV .dat");
  CLI::Option* images_option = calibrate->add_option(
      "--images", cal.images_dir, "Folder of PNG/JPG/TIF images of the target (needs --target)");
  points_option->excludes(images_option);
  calibrate->add_option("--target", cal.target_path,
                        "Kalibr target YAML (target_type: aprilgrid or checkerboard)");
  calibrate->add_option("--out", cal.out_path, "Output camera.yaml (OpenCV FileStorage)");
  calibrate->add_option("--model", cal.model,
                        "Lens model: pinhole, pinhole-k2, pinhole-radtan4, pinhole-radtan5");
  calibrate->add_flag("--skew", cal.skew, "Estimate the skew angle phi too");
  FramesArgs render_args, detect_args;
  CLI::App* render =
      app.add_subcommand("render", "Write a scenario's rendered frames (PNG) and true corners");
  AddFramesOptions(render, &render_args);
  render->add_option("--frames", render_args.frames_dir, "Output directory")->required();
  CLI::App* detect = app.add_subcommand(
      "detect", "Detection rate and corner error vs truth (RMS, bias, p95) of a scenario");
  AddFramesOptions(detect, &detect_args);
  detect->add_option("--frames", detect_args.frames_dir,
                     "Read frames + corners.csv from here (default: render in memory)");
  CLI11_PARSE(app, argc, argv);
  try {
    if (run->parsed()) return Run(config_path, out_dir, threads, quiet);
    if (render->parsed()) return RenderOrDetect(render_args, true);
    if (detect->parsed()) return RenderOrDetect(detect_args, false);
    if (calibrate->parsed()) {
      if (cal.points_path.empty() && cal.images_dir.empty()) {
        std::cerr << "calibench: calibrate: give --points FILE or --images DIR --target T.yaml\n";
        return 2;
      }
      return Calibrate(cal);
    }
  } catch (const std::exception& e) {  // A bug, not bad data: say so instead of aborting.
    std::cerr << "calibench: internal error: " << e.what() << "\n";
    return 70;
  }
  return 1;
}
