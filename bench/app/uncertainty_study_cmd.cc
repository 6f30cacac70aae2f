// `calibench uncertainty-study` (bench/app/uncertainty_study_cmd.h).
#include "bench/app/uncertainty_study_cmd.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>
#include <vector>

#include "bench/run/csv.h"
#include "metrics/projection_uncertainty_study.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

// One row of the table: a lens, the views that calibrate it, where the uncertainty is evaluated.
struct StudyCase {
  LensFamily family;
  LensModel model;
  double half_field_deg;  // The boards' reach from the axis (MakeWideBoardViews' max_angle_deg).
  int views;
  double distance_m;              // Evaluation distance (m; infinity: rays).
  double board_distance_m = 0.4;  // Camera to board centre, +-20 %.
};

std::vector<StudyCase> Cases() {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<StudyCase> cases;
  for (const int views : {6, 25}) {
    for (const double distance : {inf, 0.4}) {
      cases.push_back({LensFamily::kRadTan, LensModel::kPinholeK2, 30, views, distance});
    }
  }
  // Far boards: the same lens seen from 1.2 m (the board spans a third as much of the image).
  for (const double distance : {inf, 1.2}) {
    cases.push_back({LensFamily::kRadTan, LensModel::kPinholeK2, 20, 25, distance, 1.2});
  }
  for (const double distance : {inf, 0.4}) {
    cases.push_back({LensFamily::kRadTan, LensModel::kPinholeRadTan5, 40, 20, distance});
    cases.push_back({LensFamily::kEquidistant, LensModel::kPinholeEqui, 75, 20, distance});
    cases.push_back({LensFamily::kUnified, LensModel::kUnified, 85, 20, distance});
    cases.push_back({LensFamily::kEucm, LensModel::kEucm, 85, 20, distance});
    cases.push_back({LensFamily::kDoubleSphere, LensModel::kDoubleSphere, 95, 20, distance});
  }
  return cases;
}

std::string Fixed1(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", v);
  return text;
}

}  // namespace

int UncertaintyStudy(const UncertaintyStudyArgs& args) {
  if (args.draws < 10) {
    std::cerr << "uncertainty-study: --draws must be at least 10\n";
    return 2;
  }
  std::ostringstream table;
  table << "| lens model | field (deg) | views | boards at | distance | samples | predicted (px) | "
           "observed (px) "
           "| observed / predicted: median [p10, p90] | observed / own prediction |\n"
           "|---|---:|---:|---:|---|---:|---:|---:|---|---:|\n";
  bool all_ok = true;
  int index = 0;
  for (const StudyCase& c : Cases()) {
    // A 1024 x 1024 sensor; narrow lenses at 600 px focal length, wide ones at their family's
    // example scale of 330 px.
    const bool narrow = c.half_field_deg <= 45;
    const CameraIntrinsics truth = ExampleCamera(c.family, narrow ? 600 : 330, 511.5, 509.0);
    WideBoardOptions board;
    board.rows = 7, board.cols = 10, board.spacing_m = 0.04;
    board.num_views = c.views;
    board.max_angle_deg = c.half_field_deg;
    board.distance_m = c.board_distance_m;
    Rng rng(9000 + static_cast<uint64_t>(index++));
    const SyntheticBoardViews data = MakeWideBoardViews(truth, board, &rng);
    UncertaintyStudyOptions options;
    options.model = c.model;
    options.draws = args.draws;
    options.distance_m = c.distance_m;
    options.max_distance_to_data_px = 60;
    options.seed = 100000 * static_cast<uint64_t>(index);
    const UncertaintyStudyResult r = RunUncertaintyStudy(
        truth, data.views, data.cam_from_board, board.image_width, board.image_height, options);
    char line[512];
    const std::string distance =
        std::isinf(c.distance_m) ? "infinity" : Fixed1(c.distance_m) + " m";
    if (!r.ok) {
      all_ok = false;
      std::snprintf(line, sizeof(line), "| %s | %.0f | %d | %.1f m | %s | failed: %s |||||\n",
                    ToString(c.model), 2 * c.half_field_deg, c.views, c.board_distance_m,
                    distance.c_str(), r.message.c_str());
    } else {
      std::snprintf(line, sizeof(line),
                    "| %s | %.0f | %d | %.1f m | %s | %zu | %.3f | %.3f | %.2f [%.2f, %.2f] | %.2f "
                    "|\n",
                    ToString(c.model), 2 * c.half_field_deg, c.views, c.board_distance_m,
                    distance.c_str(), r.samples.size(), r.median_predicted_px, r.median_observed_px,
                    r.median_ratio, r.p10_ratio, r.p90_ratio, r.median_draw_ratio);
    }
    table << line;
    std::cerr << line << std::flush;
  }
  std::cout << table.str();
  if (!args.out_path.empty()) {
    std::string why;
    if (!WriteFileAtomically(args.out_path, table.str(), &why)) {
      std::cerr << "uncertainty-study: " << why << "\n";
      return 3;
    }
  }
  return all_ok ? 0 : 4;
}

}  // namespace calibench
