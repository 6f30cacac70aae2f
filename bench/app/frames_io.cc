#include "bench/app/frames_io.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "bench/run/csv.h"
#include "sim/scene_renderer.h"
#include "util/format.h"
#include "util/random.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

std::string FrameName(int k) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06d.png", k);
  return name;
}

bool CheckRendered(const ScenarioConfig& s, std::string* why) {
  if (s.points.aprilgrids.empty() || !(s.measurements.sample_rate_hz > 0)) {
    if (why) {
      *why = "scenario '" + s.name +
             "' needs AprilTag targets (points: {aprilgrids: [...]}) and "
             "measurements.sample_rate_hz > 0";
    }
    return false;
  }
  return true;
}

// The scenario's frame times, the first max_frames of them when that is set.
std::vector<double> Times(const ScenarioConfig& s, const FramesOptions& o) {
  std::vector<double> times = FrameTimes(s.measurements.sample_rate_hz, s.duration_s);
  if (o.max_frames > 0 && static_cast<int>(times.size()) > o.max_frames) {
    times.resize(o.max_frames);
  }
  return times;
}

struct Truth {
  std::map<int, Eigen::Vector2d> pixels;  // point_id -> exact pixel.
  int tags_in_view = 0;
};

}  // namespace

bool WriteRenderedFrames(const ScenarioConfig& s, const FramesOptions& o, const std::string& dir,
                         int* frames_written, std::string* why) {
  if (!CheckRendered(s, why)) return false;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    if (why) *why = dir + ": cannot create the directory: " + ec.message();
    return false;
  }
  const SceneTruth scene = s.MakeScene(s.TrialSeedOf(o.trial));
  const std::vector<AprilGrid> grids = s.points.AprilGrids();  // The renderer keeps a reference.
  const auto renderer = SceneRenderer::Create(scene, grids, s.RenderingOptions().render, why);
  if (!renderer) return false;
  const uint64_t trial_seed = s.TrialSeedOf(o.trial);
  std::string csv =
      CsvLine({"frame", "time_s", "point_id", "tag_id", "corner", "u_px", "v_px", "in_view"});
  GrayImage image;
  std::vector<BoardView> views;
  const std::vector<double> times = Times(s, o);
  const int frames = static_cast<int>(times.size());
  for (int k = 0; k < frames; ++k) {
    const double t = times[k];
    if (!renderer->Render(t, trial_seed, k, &image, &views, why)) return false;
    const cv::Mat mat(image.height, image.width, CV_8UC1, image.pixels.data());
    const std::string path = dir + "/" + FrameName(k);
    if (!cv::imwrite(path, mat)) {
      if (why) *why = path + ": cannot write the PNG";
      return false;
    }
    const std::vector<std::vector<bool>> in_view =
        TagsInView(scene.IntrinsicsAt(t), views, image.width, image.height);
    int point = 0;
    for (size_t g = 0; g < views.size(); ++g) {
      const std::vector<Eigen::Vector3d> corners = views[g].grid.CornersInBoard();
      for (size_t c = 0; c < corners.size(); ++c, ++point) {
        Eigen::Vector2d pixel;
        if (!ProjectPoint(scene.IntrinsicsAt(t), views[g].cam_from_board * corners[c], &pixel)) {
          continue;
        }
        char line[160];
        std::snprintf(line, sizeof(line), "%d,%.6f,%d,%d,%d,%.6f,%.6f,%d\n", k, t, point,
                      views[g].grid.first_id + static_cast<int>(c / 4), static_cast<int>(c % 4),
                      pixel.x(), pixel.y(), in_view[g][c / 4] ? 1 : 0);
        csv += line;
      }
    }
  }
  if (!WriteFileAtomically(dir + "/corners.csv", csv, why)) return false;
  *frames_written = frames;
  return true;
}

namespace {

// corners.csv as `calibench render` writes it: per frame, each point's exact pixel and the tags in
// view. False (and *why, with the line) for a missing file or a malformed row.
bool ReadCornerTruth(const std::string& truth_path, std::map<int, Truth>* truth, std::string* why) {
  std::ifstream in(truth_path);
  if (!in) {
    if (why) *why = truth_path + ": cannot open (written by `calibench render`)";
    return false;
  }
  std::string line;
  std::getline(in, line);  // Header.
  for (int row = 2; std::getline(in, line); ++row) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    int frame = 0, point = 0, tag = 0, corner = 0, in_view = 0;
    double t = 0, u = 0, v = 0;
    if (!(fields >> frame >> t >> point >> tag >> corner >> u >> v >> in_view)) {
      if (why) *why = truth_path + ":" + std::to_string(row) + ": expected 8 numeric fields";
      return false;
    }
    (*truth)[frame].pixels[point] = {u, v};
    (*truth)[frame].tags_in_view += (in_view && corner == 0);
  }
  return true;
}

// The unit vector from the projected centre of point_id's tag (where its projected diagonals,
// corners 0-2 and 1-3, cross) to the corner's exact pixel; false when a corner of the tag has no
// truth.
bool OutwardOfCorner(const Truth& expected, int point_id, Eigen::Vector2d* outward) {
  const int first = point_id - point_id % 4;
  Eigen::Vector2d c[4];
  for (int k = 0; k < 4; ++k) {
    const auto corner = expected.pixels.find(first + k);
    if (corner == expected.pixels.end()) return false;
    c[k] = corner->second;
  }
  const Eigen::Vector3d d02 =
      Eigen::Vector3d(c[0].x(), c[0].y(), 1).cross(Eigen::Vector3d(c[2].x(), c[2].y(), 1));
  const Eigen::Vector3d d13 =
      Eigen::Vector3d(c[1].x(), c[1].y(), 1).cross(Eigen::Vector3d(c[3].x(), c[3].y(), 1));
  const Eigen::Vector3d centre = d02.cross(d13);
  *outward = (expected.pixels.at(point_id) - centre.hnormalized()).normalized();
  return true;
}

// Reads frame `path` and checks its size against the scenario's.
bool ReadFrame(const std::string& path, const ScenarioConfig& s, cv::Mat* gray, std::string* why) {
  *gray = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (gray->empty()) {
    if (why) *why = path + ": unreadable (listed in corners.csv)";
    return false;
  }
  if (gray->cols != s.image_width || gray->rows != s.image_height) {
    if (why) {
      *why = path + ": image is " + std::to_string(gray->cols) + " x " +
             std::to_string(gray->rows) + " px, but scenario '" + s.name + "' has image_size [" +
             std::to_string(s.image_width) + ", " + std::to_string(s.image_height) + "]";
    }
    return false;
  }
  return true;
}

}  // namespace

bool DetectFrames(const ScenarioConfig& s, const FramesOptions& o, const std::string& frames_dir,
                  DetectionStats* stats, std::string* why) {
  if (!CheckRendered(s, why)) return false;
  if (frames_dir.empty()) {
    ScenarioConfig shortened = s;
    if (o.max_frames > 0) {
      shortened.duration_s = std::min(s.duration_s, o.max_frames / s.measurements.sample_rate_hz);
    }
    const SceneTruth scene = shortened.MakeScene(s.TrialSeedOf(o.trial));
    const auto source = RenderedSource::Create(scene, s.points.AprilGrids(), s.RenderingOptions(),
                                               s.TrialSeedOf(o.trial), why);
    if (!source) return false;
    *stats = source->stats();
    return true;
  }
  std::map<int, Truth> truth;
  if (!ReadCornerTruth(frames_dir + "/corners.csv", &truth, why)) return false;
  // The same detector options as the in-memory path (with a wide truth: its lens for the fit).
  const auto detector =
      FrameDetector::Create(s.points.AprilGrids(), s.RenderingOptions().detection, why);
  if (!detector) return false;
  DetectionStatsAccumulator acc;
  std::string errors_csv =
      CsvLine({"frame", "point_id", "u_px", "v_px", "du_px", "dv_px", "radial_px", "tangent_px"});
  for (const auto& [frame, expected] : truth) {
    cv::Mat gray;
    if (!ReadFrame(frames_dir + "/" + FrameName(frame), s, &gray, why)) return false;
    DetectionCounts counts;
    const std::vector<Observation> obs =
        detector->Detect(gray.data, gray.cols, gray.rows, static_cast<int>(gray.step), &counts);
    acc.AddFrame(expected.tags_in_view, counts, obs.empty());
    for (const Observation& ob : obs) {
      const auto it = expected.pixels.find(ob.point_id);
      Eigen::Vector2d outward;
      if (it == expected.pixels.end() || !OutwardOfCorner(expected, ob.point_id, &outward)) {
        continue;
      }
      const Eigen::Vector2d e = ob.pixel - it->second;
      acc.AddCornerError(e, outward, ob.crlb_px);
      if (!o.errors_path.empty()) {
        errors_csv +=
            CsvLine({std::to_string(frame), std::to_string(ob.point_id),
                     FormatNumber(it->second.x()), FormatNumber(it->second.y()),
                     FormatNumber(e.x()), FormatNumber(e.y()), FormatNumber(e.dot(outward)),
                     FormatNumber(e.dot(Eigen::Vector2d(-outward.y(), outward.x())))});
      }
    }
  }
  *stats = acc.Finish();
  return o.errors_path.empty() || WriteFileAtomically(o.errors_path, errors_csv, why);
}

std::string FormatDetectionStats(const DetectionStats& s) {
  char text[1100];
  std::snprintf(
      text, sizeof(text),
      "frames %d (%d without detections)\n"
      "tags: %ld detected of %ld fully in view: detection rate %.4f; %ld unknown ids, "
      "%ld dropped at the border, %ld unrefined (%ld more dropped: found only in a "
      "modified copy), %ld refused by the photometric fit; %ld of the detected not decoded "
      "but predicted from their neighbours (%ld predictions refused), %ld refused from "
      "AprilTag 3's corners but fitted from their neighbours', %ld fitted without pixels that "
      "disagree with their pattern (covered in part)\n"
      "corner error vs truth over %ld corners: RMS %.4f px, bias (%.4f, %.4f) px, "
      "p95 %.4f px; along the tag diagonals: radial (outward) bias %.4f px, tangential "
      "%.4f px; Cramer-Rao std per axis (RMS) %.4f px\n",
      s.frames, s.frames_without_detections, s.tags_detected, s.tags_expected, s.DetectionRate(),
      s.unknown_tags, s.border_tags, s.unrefined_tags, s.unrefined_copy_tags, s.refused_tags,
      s.predicted_tags, s.refused_predictions, s.refitted_tags, s.covered_tags, s.corners, s.rms_px,
      s.bias_x_px, s.bias_y_px, s.p95_px, s.bias_radial_px, s.bias_tangent_px, s.crlb_rms_px);
  return text;
}

}  // namespace calibench
