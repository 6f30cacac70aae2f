// `calibench uncertainty-study` (bench/app/uncertainty_study_cmd.h).
#include "bench/app/uncertainty_study_cmd.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>
#include <vector>

#include "bench/run/csv.h"
#include "detect/chessboard.h"
#include "metrics/projection_uncertainty_study.h"
#include "sim/checkerboard_image.h"
#include "sim/synthetic.h"
#include "util/parallel_for.h"
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

// A rendered case: a checkerboard of 7 x 10 inner corners (2.5 cm squares; rows + cols odd, so
// the detector's corner order is unambiguous) seen by a 640 x 480 camera from ~0.5 m.
struct RenderedCase {
  LensModel model;
  int views;
};

std::vector<RenderedCase> RenderedCases() {
  return {{LensModel::kPinholeK2, 15}, {LensModel::kPinholeRadTan5, 20}};
}

// What the rendered draws measured: per draw, the views' detected corners (each matched to the
// nearest exact projection: the board's corners are >= 10 px apart, the detector's errors ~0.05
// px). A corner's error splits into what changes from draw to draw (the image noise's share: what
// the covariance propagates) and what does not (the same geometry rendered on the same pixel grid:
// a fixed offset per corner, which no re-solve averages out and no covariance sees).
struct RenderedDraws {
  std::vector<std::vector<View>> draws;  // Draws in which every view was detected whole.
  int failed_draws = 0;
  double corner_std_px = 0.0;    // Per axis: the draw-to-draw std of a corner, pooled.
  double corner_fixed_px = 0.0;  // Per axis: RMS over the corners of their mean error.
};

RenderedDraws RenderAndDetect(const CameraIntrinsics& truth, const CheckerboardPattern& pattern,
                              const SyntheticBoardViews& exact, int num_draws, uint64_t seed,
                              int threads) {
  CheckerboardImageOptions image;
  image.width = 640, image.height = 480;
  image.blur_sigma_px = 1.0;     // The PSF's sigma (a 3 x 3 finer shading grid).
  image.noise_sigma_gray = 2.0;  // Of 255: a well-exposed industrial camera.
  ChessboardOptions detector;
  detector.cols = pattern.cols, detector.rows = pattern.rows;
  const size_t num_views = exact.views.size();
  const size_t items = static_cast<size_t>(num_draws) * num_views;
  std::vector<std::vector<Eigen::Vector2d>> detected(items);
  std::vector<char> found(items, 0);
  ParallelFor(items, threads, [&](int /*worker*/, size_t i) {
    Rng noise(seed + i, RngStream::kPixelNoise);
    GrayImage gray;
    std::string why, how;
    if (!RenderCheckerboard(truth, exact.cam_from_board[i % num_views], pattern, image, &noise,
                            &gray, &why)) {
      return;
    }
    found[i] = FindChessboardCorners(GrayImageView(gray), detector, &detected[i], &how) ? 1 : 0;
  });
  RenderedDraws out;
  // Per corner (view v, point j): the sum and the sum of squares of its error over the draws.
  std::vector<std::vector<Eigen::Vector2d>> sum(num_views), sum_squares(num_views);
  for (size_t v = 0; v < num_views; ++v) {
    sum[v].assign(exact.views[v].pixels.size(), Eigen::Vector2d::Zero());
    sum_squares[v] = sum[v];
  }
  for (int d = 0; d < num_draws; ++d) {
    std::vector<View> views(num_views);
    std::vector<std::vector<size_t>> index(num_views);
    bool whole = true;
    for (size_t v = 0; v < num_views && whole; ++v) {
      const size_t i = static_cast<size_t>(d) * num_views + v;
      const View& truth_view = exact.views[v];
      whole = found[i] && detected[i].size() == truth_view.pixels.size();
      for (size_t k = 0; whole && k < detected[i].size(); ++k) {
        size_t nearest = 0;
        for (size_t j = 1; j < truth_view.pixels.size(); ++j) {
          if ((truth_view.pixels[j] - detected[i][k]).squaredNorm() <
              (truth_view.pixels[nearest] - detected[i][k]).squaredNorm()) {
            nearest = j;
          }
        }
        views[v].points.push_back(truth_view.points[nearest]);
        views[v].pixels.push_back(detected[i][k]);
        index[v].push_back(nearest);
        whole = (truth_view.pixels[nearest] - detected[i][k]).norm() < 1.0;
      }
    }
    if (!whole) {
      ++out.failed_draws;
      continue;
    }
    for (size_t v = 0; v < num_views; ++v) {
      for (size_t k = 0; k < views[v].pixels.size(); ++k) {
        const Eigen::Vector2d error = views[v].pixels[k] - exact.views[v].pixels[index[v][k]];
        sum[v][index[v][k]] += error;
        sum_squares[v][index[v][k]] += error.cwiseProduct(error);
      }
    }
    out.draws.push_back(std::move(views));
  }
  const double n = static_cast<double>(out.draws.size());
  if (n >= 2) {
    double variance = 0.0, fixed = 0.0;
    long corners = 0;
    for (size_t v = 0; v < num_views; ++v) {
      for (size_t j = 0; j < sum[v].size(); ++j) {
        const Eigen::Vector2d mean = sum[v][j] / n;
        variance += ((sum_squares[v][j] - n * mean.cwiseProduct(mean)) / (n - 1)).sum();
        fixed += mean.squaredNorm();
        ++corners;
      }
    }
    out.corner_std_px = std::sqrt(variance / (2.0 * static_cast<double>(corners)));
    out.corner_fixed_px = std::sqrt(fixed / (2.0 * static_cast<double>(corners)));
  }
  return out;
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
  if (args.rendered) {
    table
        << "\nRendered: every draw renders the same views again (blur 1 px, noise 2 gray levels, "
           "8-bit) and detects them (detect/chessboard.h); predicted with the corners' "
           "draw-to-draw std (per axis, pooled); their fixed error (the RMS of each corner's mean "
           "error) is the detector's bias, which no covariance sees.\n\n"
           "| lens model | views | draws | corner std (px/axis) | corner fixed error (px/axis) | "
           "samples "
           "| predicted (px) | observed (px) | observed / predicted: median [p10, p90] | "
           "observed / own prediction |\n"
           "|---|---:|---:|---:|---:|---:|---:|---:|---|---:|\n";
  }
  for (const RenderedCase& c : args.rendered ? RenderedCases() : std::vector<RenderedCase>{}) {
    const CameraIntrinsics truth = ExampleCamera(LensFamily::kRadTan, 600, 319.5, 239.5);
    CheckerboardPattern pattern;
    pattern.rows = 7, pattern.cols = 10, pattern.square_m = 0.025;
    SyntheticBoardOptions board;
    board.rows = pattern.rows, board.cols = pattern.cols, board.spacing_m = pattern.square_m;
    board.num_views = c.views;
    board.distance_m = 0.5;
    board.max_tilt_deg = 35;
    Rng rng(7000 + static_cast<uint64_t>(index++));
    const SyntheticBoardViews exact = MakeBoardViews(truth, board, &rng);
    const RenderedDraws measured = RenderAndDetect(
        truth, pattern, exact, args.draws, 100000 * static_cast<uint64_t>(index), args.threads);
    UncertaintyStudyOptions options;
    options.model = c.model;
    options.pixel_sigma_px = measured.corner_std_px;
    options.draws = static_cast<int>(measured.draws.size());
    options.max_distance_to_data_px = 60;
    const UncertaintyStudyResult r =
        RunUncertaintyStudy(truth, exact.views, exact.cam_from_board, board.image_width,
                            board.image_height, options, &measured.draws);
    char line[512];
    if (!r.ok) {
      all_ok = false;
      std::snprintf(line, sizeof(line),
                    "| %s | %d | %zu | failed: %s (%d draws with a view not detected whole) "
                    "|||||||\n",
                    ToString(c.model), c.views, measured.draws.size(), r.message.c_str(),
                    measured.failed_draws);
    } else {
      std::snprintf(line, sizeof(line),
                    "| %s | %d | %zu | %.4f | %.4f | %zu | %.4f | %.4f | %.2f [%.2f, %.2f] | %.2f "
                    "|\n",
                    ToString(c.model), c.views, measured.draws.size(), measured.corner_std_px,
                    measured.corner_fixed_px, r.samples.size(), r.median_predicted_px,
                    r.median_observed_px, r.median_ratio, r.p10_ratio, r.p90_ratio,
                    r.median_draw_ratio);
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
