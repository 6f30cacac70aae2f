// calibench: the command-line entry point. Thin: parses arguments and calls the bench library.
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "bench/app/calibrate_cmd.h"
#include "bench/app/compare_cmd.h"
#include "bench/app/corner_bias_cmd.h"
#include "bench/app/corners_csv.h"
#include "bench/app/frames_io.h"
#include "bench/app/report_cmd.h"
#include "bench/app/target_cmd.h"
#include "bench/app/uncertainty_study_cmd.h"
#include "bench/config/config_io.h"
#include "bench/config/config_reference.h"
#include "bench/run/csv.h"
#include "bench/run/run_dir.h"
#include "bench/run/runner.h"
#include "bench/run/table.h"
#include "calib/detect_images.h"
#include "calib/model_select.h"
#include "calib/solver_logging.h"
#include "util/opencv_threads.h"

namespace {

// SIGINT / SIGTERM during `run`: finish writing the task in hand, then stop (run.partial stays
// resumable with --resume).
volatile std::sig_atomic_t g_stop_requested = 0;
void RequestStop(int) { g_stop_requested = 1; }

void ProgressBar(long done, long total) {
  const int width = 40;
  const int filled = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\r[%s%s] %ld/%ld tasks", std::string(filled, '#').c_str(),
               std::string(width - filled, '.').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

struct RunArgs {
  std::string config_path, out_dir, shard = "1/1";
  int threads = 0;
  bool quiet = false, resume = false;
};

int Run(const RunArgs& args) {
  calibench::RunConfig config;
  std::string why;
  if (!calibench::LoadRunConfig(args.config_path, &config, &why)) {
    std::cerr << "calibench: invalid configuration: " << why << "\n";
    return 2;
  }
  calibench::RunDirOptions options;
  if (!options.shard.Parse(args.shard, &why)) {
    std::cerr << "calibench: " << why << "\n";
    return 2;
  }
  for (const calibench::ScenarioConfig& s : config.scenarios) {
    if (s.truth.allow_improper_rotation && s.sweep_point.index == 0) {
      std::cerr << "calibench: warning: scenario '" << s.name
                << "': truth R_C is allowed to be improper (det = -1), to reproduce a source "
                   "that printed such a matrix; no real camera has one\n";
    }
  }
  options.out_dir = args.out_dir;
  options.threads = args.threads;
  options.resume = args.resume;
  if (!args.quiet && ::isatty(STDERR_FILENO)) options.progress = ProgressBar;
  options.should_stop = [] { return g_stop_requested != 0; };
  std::signal(SIGINT, RequestStop);
  std::signal(SIGTERM, RequestStop);
  const calibench::RunDirSummary summary = calibench::RunToDirectory(config, options);
  if (!summary.ok) {
    std::cerr << "calibench: " << summary.message << "\n";
    return 3;
  }
  if (!args.quiet) {
    std::ifstream table(args.out_dir + "/table.md");
    std::cout << table.rdbuf();
  }
  std::cerr << "calibench: " << args.out_dir << ": " << summary.tasks_run << " tasks run";
  if (summary.tasks_resumed > 0) std::cerr << ", " << summary.tasks_resumed << " resumed";
  std::cerr << " (shard " << options.shard.ToString() << ", " << summary.tasks_total << " tasks), "
            << summary.rows_written << " rows written in " << summary.wall_s << " s"
            << (summary.message.empty() ? "" : "; " + summary.message) << "\n";
  return 0;
}

int Merge(const std::vector<std::string>& dirs, const std::string& out_dir) {
  std::string why;
  if (!calibench::MergeRunDirectories(dirs, out_dir, &why)) {
    std::cerr << "calibench: merge: " << why << "\n";
    return 3;
  }
  std::cerr << "calibench: merged " << dirs.size() << " shards into " << out_dir << "\n";
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

struct DetectImagesArgs {
  std::string images_dir, target_path, out_path;
};

// detect --images DIR --target T.yaml [--out corners.csv] (detect_images.h).
int DetectImages(const DetectImagesArgs& args) {
  calibench::CalibrationTarget target;
  std::string why;
  if (args.target_path.empty()) {
    std::cerr << "calibench: detect: --images needs --target TARGET.yaml (Kalibr aprilgrid or "
                 "checkerboard)\n";
    return 2;
  }
  if (!calibench::LoadTargetYaml(args.target_path, &target, &why)) {
    std::cerr << "calibench: --target: " << why << "\n";
    return 2;
  }
  std::vector<calibench::ImageCorners> images;
  if (!calibench::DetectImageCorners(args.images_dir, target, &images, &why)) {
    std::cerr << "calibench: detect --images: " << why << "\n";
    return 2;
  }
  std::cout << calibench::FormatImageCorners(images, target);
  if (args.out_path.empty()) return 0;
  if (!calibench::WriteFileAtomically(args.out_path, calibench::ImageCornersCsv(images), &why)) {
    std::cerr << "calibench: " << why << "\n";
    return 3;
  }
  std::cerr << "calibench: wrote " << args.out_path << "\n";
  return 0;
}

void AddFramesOptions(CLI::App* command, FramesArgs* args, bool config_required = true) {
  CLI::Option* config =
      command->add_option("config", args->config_path, "Scenario file (YAML) with aprilgrids")
          ->check(CLI::ExistingFile);
  if (config_required) config->required();
  command->add_option("--scenario", args->scenario, "Scenario name (default: the first)");
  command->add_option("--trial", args->options.trial, "Trial index (noise seed)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--max-frames", args->options.max_frames, "At most this many frames")
      ->check(CLI::NonNegativeNumber);
}

}  // namespace

namespace {

// `run`: its options into *run_args.
CLI::App* AddRunCommand(CLI::App* app, RunArgs* run_args) {
  CLI::App* run = app->add_subcommand("run", "Run the scenarios and sweeps of a YAML config");
  run->add_option("config", run_args->config_path, "Scenario file or entry point (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--out", run_args->out_dir,
                  "Output directory (runs.csv, summary.csv, timings.csv, curves.csv, table.md)")
      ->required();
  run->add_option("--threads", run_args->threads, "Worker threads (0: all cores)")
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--quiet", run_args->quiet, "No table on stdout, no progress bar");
  run->add_flag("--resume", run_args->resume,
                "Continue an interrupted run in --out (kill -9 included)");
  run->add_option("--shard", run_args->shard, "Run only slice K of N (K/N); see `merge`");
  return run;
}

// `calibrate`: its options into *cal.
CLI::App* AddCalibrateCommand(CLI::App* app, calibench::CalibrateArgs* cal) {
  CLI::App* calibrate =
      app->add_subcommand("calibrate", "Calibrate a camera from point files or from images");
  CLI::Option* points_option = calibrate->add_option(
      "--points", cal->points_path, "Zhang folder (Model.txt, data*.txt) or OpenCV .dat");
  CLI::Option* images_option = calibrate->add_option(
      "--images", cal->images,
      "Folder of PNG/JPG/TIF images of the target (needs --target). A rig: one --images per "
      "camera, each a folder or a quoted glob ('dir/left*.jpg'); images paired by the number "
      "(else the stem) in their names");
  points_option->excludes(images_option);
  calibrate->add_option("--target", cal->target_path,
                        "Kalibr target YAML (target_type: aprilgrid or checkerboard)");
  calibrate->add_option("--out", cal->out_path,
                        "Output camera file (default camera.yaml; format from --format or the "
                        "extension: .cameramodel = mrcal, *camchain*.yaml = kalibr, else opencv)");
  calibrate->add_option("--format", cal->format, "Output format: opencv, kalibr or mrcal");
  calibrate->add_option("--model", cal->model,
                        "Lens model: " + calibench::LensModelList() +
                            ", or auto (fit pinhole-radtan4/5, pinhole-equi, unified, eucm, "
                            "double-sphere; pick the simplest within noise of the best "
                            "held-out RMS). A rig: one model for every camera, or a "
                            "comma-separated list, one per --images");
  calibrate->add_flag("--skew", cal->skew, "Estimate the skew angle phi too");
  calibrate
      ->add_option("--init", cal->init_path,
                   "A camera file (opencv, kalibr or mrcal) as the initial guess instead of "
                   "zhang; its lens model unless --model is given")
      ->check(CLI::ExistingFile);
  calibrate
      ->add_option("--corner-iterations", cal->corner_iterations,
                   "With --images and a lens model that distorts: re-fit the corners (tags or "
                   "checkerboard X-junctions) through the estimate and recalibrate at most this "
                   "often, until f moves by < 0.1 std, or (aprilgrid) a re-fit is predicted to "
                   "move it less (0: detect once)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  calibrate
      ->add_option("--threads", cal->threads,
                   "With --images: read and detect the images on this many threads (0: every "
                   "core; the result does not depend on it)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  calibrate
      ->add_option("--corner-refinement", cal->corner_refinement,
                   "With --images (aprilgrid): none, edge_fit or photometric (default; the "
                   "edge fit with curved edges for the wide models without --init). Other than "
                   "photometric: detect once, no re-fit through the lens")
      ->check(CLI::IsMember(
          {calibench::CornerRefinementName(calibench::CornerRefinement::kNone),
           calibench::CornerRefinementName(calibench::CornerRefinement::kEdgeFit),
           calibench::CornerRefinementName(calibench::CornerRefinement::kPhotometric)}));
  calibrate->add_flag("--no-tag-prediction", cal->no_tag_prediction,
                      "With --images (aprilgrid, photometric): keep only the tags AprilTag 3 "
                      "decodes; by default a grid's missed tags are fitted where their fitted "
                      "neighbours put them");
  calibrate
      ->add_option("--jackknife", cal->jackknife,
                   "Leave-one-view-out std beside the formal one: auto (at most 30 views), on or "
                   "off")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  calibrate->add_flag("--no-page", cal->no_page,
                      "Do not write the page of figures (STEM.md and its PNGs) beside --out");
  calibrate->add_flag("--cross-validate", cal->cross_validate,
                      "Also calibrate the two halves of the views (alternate views) apart and "
                      "compare them over the image against their uncertainty");
  calibrate->add_flag("--evaluate", cal->evaluate,
                      "With --init: keep that camera fixed, fit only each image's pose, report "
                      "the reprojection RMS per image and flag outliers. A rig (--init a "
                      "camchain): keep the rig fixed, report its reprojection and epipolar errors");
  calibrate->add_option("--rectified", cal->rectified_path,
                        "A rig: write the first two cameras' rectified images of the first frame "
                        "both saw side by side with horizontal lines (default: beside --out, "
                        "<stem>-rectified.png)");
  return calibrate;
}

// `detect`: a scenario's options into *detect_args, the --images form's into *detect_images.
CLI::App* AddDetectCommand(CLI::App* app, FramesArgs* detect_args,
                           DetectImagesArgs* detect_images) {
  CLI::App* detect = app->add_subcommand(
      "detect",
      "Detection rate and corner error vs truth (RMS, bias, p95) of a scenario; or, with "
      "--images, the target's corners found in a folder of images");
  AddFramesOptions(detect, detect_args, false);
  detect->add_option("--images", detect_images->images_dir,
                     "Folder of PNG/JPG/TIF images (8- or 16-bit) of the target (needs --target)");
  detect->add_option("--target", detect_images->target_path,
                     "With --images: Kalibr target YAML (aprilgrid or checkerboard)");
  detect->add_option("--out", detect_images->out_path,
                     "With --images: write image,tag_id,corner,u_px,v_px,crlb_px per corner (CSV)");
  detect->add_option("--frames", detect_args->frames_dir,
                     "Read frames + corners.csv from here (default: render in memory)");
  detect->add_option("--errors", detect_args->options.errors_path,
                     "With --frames: write every matched corner's error (CSV)");
  return detect;
}

// `detect` parsed: the --images form or a scenario's frames, not both.
int Detect(const FramesArgs& detect_args, const DetectImagesArgs& detect_images,
           bool images_given) {
  if (images_given) {
    if (!detect_args.config_path.empty()) {
      std::cerr << "calibench: detect: give a scenario CONFIG or --images DIR, not both\n";
      return 2;
    }
    return DetectImages(detect_images);
  }
  if (detect_args.config_path.empty()) {
    std::cerr << "calibench: detect: give a scenario CONFIG, or --images DIR --target "
                 "T.yaml\n";
    return 2;
  }
  return RenderOrDetect(detect_args, false);
}

// `corner-bias`: its options into *bias_args.
CLI::App* AddCornerBiasCommand(CLI::App* app, calibench::CornerBiasArgs* bias_args) {
  CLI::App* corner_bias =
      app->add_subcommand("corner-bias",
                          "Corner bias and noise of render + detect + refine vs exact projections, "
                          "against viewing angle, tag size, blur and image position");
  corner_bias->add_option("--out", bias_args->out_path, "Output CSV")->required();
  corner_bias->add_option("--views", bias_args->views,
                          "Sub-pixel shifted views per case (default 8)");
  corner_bias->add_option("--draws", bias_args->draws, "Noise draws per view (default 8)");
  corner_bias->add_option("--supersample", bias_args->supersample,
                          "Renderer samples per pixel side where a board's outline meets the "
                          "background (default 16; pixels on the board hold exact cell areas)");
  corner_bias->add_option("--threads", bias_args->threads, "Worker threads (default 2)");
  return corner_bias;
}

// `compare`: its options into *compare_args.
CLI::App* AddCompareCommand(CLI::App* app, calibench::CompareArgs* compare_args) {
  CLI::App* compare = app->add_subcommand(
      "compare",
      "Do two camera files (any format and lens family) describe the same camera? Their "
      "projection difference after the fitted rotation, against their uncertainty");
  compare->add_option("A", compare_args->a_path, "The first camera file")->required();
  compare->add_option("B", compare_args->b_path, "The second camera file")->required();
  compare->add_option("--out", compare_args->out_path, "The difference heatmap (PNG)");
  compare->add_option("--distance", compare_args->distance_m,
                      "Compare points at this distance (m; default: rays at infinity)");
  compare->add_flag("--no-rotation", compare_args->no_rotation,
                    "Do not fit the rotation between the two camera frames");
  return compare;
}

// `uncertainty-study`: its options into *study_args.
CLI::App* AddUncertaintyStudyCommand(CLI::App* app, calibench::UncertaintyStudyArgs* study_args) {
  CLI::App* study = app->add_subcommand(
      "uncertainty-study",
      "Monte Carlo validation of the projection uncertainty over lens families, views and "
      "distances (the table of docs/results/uncertainty.md)");
  study->add_option("--out", study_args->out_path, "Markdown table (also printed)");
  study->add_option("--draws", study_args->draws, "Re-solves per case (default 100)");
  study->add_flag("--rendered", study_args->rendered,
                  "Also on rendered checkerboard images, detected again at every draw");
  study->add_option("--threads", study_args->threads,
                    "Rendering and detection in parallel (0: all cores)");
  return study;
}

// `target`: its options into *target_args.
CLI::App* AddTargetCommand(CLI::App* app, calibench::TargetArgs* target_args) {
  CLI::App* target = app->add_subcommand(
      "target", "A printable target: vector PDF at exact size, PNG at --dpi, Kalibr target YAML");
  target->add_option("--type", target_args->type, "aprilgrid (default) or checkerboard");
  target->add_option("--rows", target_args->rows, "Tags (aprilgrid) or inner corners (default 6)");
  target->add_option("--cols", target_args->cols, "Tags (aprilgrid) or inner corners (default 6)");
  target->add_option("--size", target_args->size_m,
                     "Tag edge incl. border, or square edge, in m (default 0.088)");
  target->add_option("--spacing", target_args->spacing,
                     "aprilgrid: gap between tags / tag size (default 0.3)");
  target->add_option("--border", target_args->border_bits,
                     "aprilgrid: black border bits, 1 or 2 (default 2, Kalibr)");
  target->add_option("--family", target_args->family, "aprilgrid: tag family (default tag36h11)");
  target->add_option("--first-id", target_args->first_id, "aprilgrid: id of the bottom-left tag");
  target->add_option("--margin", target_args->margin_m, "White margin in m (default 0.02)");
  target->add_option("--dpi", target_args->dpi, "Resolution of the PNG (default 300)");
  target->add_option("--out", target_args->out_path,
                     "Output PDF; the PNG and YAML are written beside it (default board.pdf)");
  return target;
}

}  // namespace

// CLI11 throws from setup only on a programming error (a duplicate option name).
// Output directories and where their combination goes (merge).
struct DirsArgs {
  std::vector<std::string> dirs;
  std::string out;
};

CLI::App* AddMergeCommand(CLI::App* app, DirsArgs* a) {
  CLI::App* merge = app->add_subcommand("merge", "Combine the shard directories of one sweep");
  merge->add_option("dirs", a->dirs, "Shard output directories 1/N..N/N")
      ->required()
      ->check(CLI::ExistingDirectory);
  merge->add_option("--out", a->out, "Merged output directory")->required();
  return merge;
}

CLI::App* AddReportCommand(CLI::App* app, calibench::ReportArgs* a) {
  CLI::App* report = app->add_subcommand(
      "report", "Plots and paired tests of run directories (report.md + PNGs; Python)");
  report->add_option("dirs", a->dirs, "Run output directories")
      ->required()
      ->check(CLI::ExistingDirectory);
  report->add_option("--out", a->out, "Report directory (default: FIRST_DIR/report)");
  report->add_option("--python", a->python,
                     "Python interpreter (default: $CALIBENCH_PYTHON, else python3 on PATH, "
                     "else /usr/bin/python3)");
  return report;
}

CLI::App* AddRenderCommand(CLI::App* app, FramesArgs* a) {
  CLI::App* render =
      app->add_subcommand("render", "Write a scenario's rendered frames (PNG) and true corners");
  AddFramesOptions(render, a);
  render->add_option("--frames", a->frames_dir, "Output directory")->required();
  return render;
}

CLI::App* AddMethodsCommand(CLI::App* app, std::string* type) {
  CLI::App* methods = app->add_subcommand(
      "methods",
      "List the method types (description, enabled by default) and their options: type, default, "
      "unit, meaning (Markdown)");
  methods->add_option("--type", *type, "Only this method type");
  return methods;
}

int Methods(const std::string& type) {
  std::string text, why;
  if (!calibench::MethodsReference(type, &text, &why)) {
    std::cerr << "calibench: methods: " << why << "\n";
    return 2;
  }
  std::cout << text;
  return 0;
}

int CalibrateCommand(const CLI::App& calibrate, calibench::CalibrateArgs* cal) {
  if (cal->points_path.empty() && cal->images.empty()) {
    std::cerr << "calibench: calibrate: give --points FILE or --images DIR --target T.yaml\n";
    return 2;
  }
  cal->model_given = calibrate.get_option("--model")->count() > 0;
  cal->out_given = calibrate.get_option("--out")->count() > 0;
  return calibench::Calibrate(*cal);
}

int main(int argc, char** argv) {  // NOLINT(bugprone-exception-escape)
  // A file-size limit (ulimit -f) then fails the write with EFBIG, which is reported and resumable,
  // instead of killing the process.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"calibench: adaptive vs batch camera calibration, on identical data"};
  app.require_subcommand(1);
  calibench::ConfigureSolverLogging(argv[0], false);
  calibench::UseSequentialOpenCv();  // calibench parallelises over trials and images itself.
  bool verbose = false;
  app.add_flag("--verbose", verbose,
               "Show the solvers' log: Ceres's per-iteration lines and its step warnings");
  app.fallthrough();  // --verbose after the subcommand too.
  RunArgs run_args;
  CLI::App* run = AddRunCommand(&app, &run_args);
  DirsArgs merge_args;
  CLI::App* merge = AddMergeCommand(&app, &merge_args);
  calibench::ReportArgs report_args;
  CLI::App* report = AddReportCommand(&app, &report_args);
  calibench::CalibrateArgs cal;
  CLI::App* calibrate = AddCalibrateCommand(&app, &cal);
  FramesArgs render_args, detect_args;
  CLI::App* render = AddRenderCommand(&app, &render_args);
  DetectImagesArgs detect_images;
  CLI::App* detect = AddDetectCommand(&app, &detect_args, &detect_images);
  calibench::CornerBiasArgs bias_args;
  CLI::App* corner_bias = AddCornerBiasCommand(&app, &bias_args);
  calibench::TargetArgs target_args;
  CLI::App* target = AddTargetCommand(&app, &target_args);
  calibench::CompareArgs compare_args;
  CLI::App* compare = AddCompareCommand(&app, &compare_args);
  calibench::UncertaintyStudyArgs study_args;
  CLI::App* study = AddUncertaintyStudyCommand(&app, &study_args);
  CLI::App* config_reference =
      app.add_subcommand("config-reference",
                         "Print the scenario format's reference (Markdown) from its declarations: "
                         "the generated part "
                         "of docs/configuration.md");
  std::string methods_type;
  CLI::App* methods = AddMethodsCommand(&app, &methods_type);
  CLI11_PARSE(app, argc, argv);
  if (verbose) calibench::ConfigureSolverLogging(argv[0], true);
  try {
    if (run->parsed()) return Run(run_args);
    if (merge->parsed()) return Merge(merge_args.dirs, merge_args.out);
    if (report->parsed()) {
      if (report_args.out.empty()) report_args.out = report_args.dirs[0] + "/report";
      return calibench::Report(report_args, argv[0]);
    }
    if (render->parsed()) return RenderOrDetect(render_args, true);
    if (detect->parsed()) {
      return Detect(detect_args, detect_images, detect->get_option("--images")->count() > 0);
    }
    if (corner_bias->parsed()) return calibench::CornerBias(bias_args);
    if (target->parsed()) return calibench::WriteTarget(target_args);
    if (study->parsed()) return calibench::UncertaintyStudy(study_args);
    if (compare->parsed()) return calibench::Compare(compare_args);
    if (config_reference->parsed()) {
      std::cout << calibench::ConfigurationReference();
      return 0;
    }
    if (methods->parsed()) return Methods(methods_type);
    if (calibrate->parsed()) return CalibrateCommand(*calibrate, &cal);
  } catch (const std::exception& e) {  // A bug, not bad data: say so instead of aborting.
    std::cerr << "calibench: internal error: " << e.what() << "\n";
    return 70;
  }
  return 1;
}
