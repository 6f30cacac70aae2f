#include "calib/image_points.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "detect/chessboard.h"
#include "detect/x_junction.h"
#include "util/parallel_for.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

// A checkerboard corner's X-junction refinement (detect/x_junction.h) sees its four squares only:
// its window's radius is at most half the corner's reach, the distance to the nearest far side of
// an adjacent square (a neighbouring corner's distance for square squares, less for a tilted
// board's sheared ones). A corner whose reach is below kMinSquareReachPx is left out: measured on
// rendered fisheye views (2 gray levels of noise, 1 px blur), corners of squares 6.5-8 px across
// came out 0.2-0.5 px off where the others were within 0.16 px. So the radius is at least 4 px,
// and the refinement's own move limit (3 px) keeps a corner off its neighbours' junctions.
constexpr double kMinSquareReachPx = 8.0;

// The reach of inner corner (r, c) of the rows x cols corners `found` (row-major; above).
double SquareReachPx(const std::vector<Eigen::Vector2d>& found, int rows, int cols, int r, int c) {
  auto at = [&](int rr, int cc) -> const Eigen::Vector2d& { return found[rr * cols + cc]; };
  auto distance_to_line = [](const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                             const Eigen::Vector2d& b) {
    const Eigen::Vector2d d = b - a;
    const double n = d.norm();
    return n > 0 ? std::abs(d.x() * (p - a).y() - d.y() * (p - a).x()) / n : (p - a).norm();
  };
  double reach = std::numeric_limits<double>::infinity();
  for (const int dr : {-1, 1}) {
    for (const int dc : {-1, 1}) {
      if (r + dr < 0 || r + dr >= rows || c + dc < 0 || c + dc >= cols) continue;
      const Eigen::Vector2d &p = at(r, c), &across = at(r + dr, c + dc);
      reach = std::min({reach, distance_to_line(p, at(r, c + dc), across),
                        distance_to_line(p, at(r + dr, c), across)});
    }
  }
  return reach;
}

// A view needs this many points: more than a homography's 4, so that a view says something.
constexpr size_t kMinViewPoints = 8;

// The checkerboard's corners (detect/chessboard.h, the sector-based detector first for a wide
// `lens`; taken from *found when `reuse`, else stored there), refined as X-junctions through
// `camera` when given (a corner whose refinement fails is left out, and counted in *how), with
// their board points: corner (r, c) of the targetCols x targetRows inner corners is at (c *
// colSpacing, r * rowSpacing, 0).
bool FindCheckerboard(const cv::Mat& gray, const CalibrationTarget& t, LensFamily lens,
                      const CameraIntrinsics* camera, bool reuse,
                      std::vector<Eigen::Vector2d>* found, View* view, std::string* how) {
  const GrayImageView image(gray.data, gray.cols, gray.rows, static_cast<int>(gray.step));
  if (!reuse) {
    ChessboardOptions options;
    options.cols = t.cols;
    options.rows = t.rows;
    options.sector_based_first = lens != LensFamily::kRadTan;  // Wide lenses bend the board.
    if (!FindChessboardCorners(image, options, found, how)) found->clear();
  } else {
    *how = "the first pass's corners";
  }
  const size_t expected = static_cast<size_t>(t.cols) * static_cast<size_t>(t.rows);
  if (found->size() != expected) return false;
  int failed = 0;
  std::string first_reason;
  for (int r = 0; r < t.rows; ++r) {
    for (int c = 0; c < t.cols; ++c) {
      Eigen::Vector2d pixel = (*found)[r * t.cols + c];
      if (camera) {
        const double reach = SquareReachPx(*found, t.rows, t.cols, r, c);
        if (!(reach >= kMinSquareReachPx)) {
          if (failed++ == 0) first_reason = "its squares are too thin in the image";
          continue;
        }
        XJunctionOptions options;
        options.radius_px = std::min(0.5 * reach, options.radius_px);
        const XJunctionSummary s = RefineXJunction(image, &*camera, options, &pixel);
        if (!s.converged) {
          if (failed++ == 0) first_reason = s.message;
          continue;
        }
      }
      view->points.emplace_back(c * t.col_spacing_m, r * t.row_spacing_m, 0.0);
      view->pixels.push_back(pixel);
    }
  }
  if (camera) {
    *how += ", X-junctions through the lens";
    if (failed > 0) {
      *how += " (" + std::to_string(failed) + " corners left out: " + first_reason + ")";
    }
  }
  return true;
}

}  // namespace

FrameDetectorOptions ImageDetectorOptions(const ImagePointOptions& image) {
  FrameDetectorOptions options;
  // The photometric model draws a tag through a homography, which a fisheye's bent edges break:
  // without a camera to draw it through, the wide families (all but radtan) keep the curved-edge
  // fit.
  options.refine.curved_edges = image.lens != LensFamily::kRadTan;
  if (image.camera) {
    options.camera = *image.camera;
    // A wide lens: boards near its image circle may decode no tag (FrameDetectorOptions).
    if (options.refine.curved_edges) options.perspective_views_below_tags = 4;
  } else if (options.refine.curved_edges) {
    options.refinement = CornerRefinement::kEdgeFit;
  }
  if (image.refinement) options.refinement = *image.refinement;
  options.predict_missing_tags = image.predict_missing_tags;
  return options;
}

bool IsImageFile(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp"}) {
    if (ext == e) return true;
  }
  return false;
}

bool ListImageFiles(const std::string& dir, std::vector<std::string>* files, std::string* why) {
  files->clear();
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file() && IsImageFile(it->path().string()))
      files->push_back(it->path().string());
  }
  if (ec) {
    if (why) *why = dir + ": cannot list the folder: " + ec.message();
    return false;
  }
  if (files->empty()) {
    if (why) *why = dir + ": no images (png, jpg, jpeg, tif, tiff, bmp) in the folder";
    return false;
  }
  std::sort(files->begin(), files->end());
  return true;
}

namespace {

// ReadGray8 into an OpenCV image.
bool ReadGray8Mat(const std::string& path, cv::Mat* gray, std::string* why, std::string* note) {
  note->clear();
  cv::Mat raw;
  try {
    raw = cv::imread(path, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  } catch (const cv::Exception& e) {
    raw.release();
  }
  gray->release();
  if (raw.empty()) {
    std::error_code size_ec;
    const auto bytes = fs::file_size(path, size_ec);
    *why = size_ec      ? "unreadable: " + size_ec.message()
           : bytes == 0 ? "unreadable: empty file (0 bytes)"
                        : "unreadable: cannot be decoded (not an image, or truncated)";
    return false;
  }
  if (raw.depth() == CV_8U) {
    *gray = raw;
    return true;
  }
  if (raw.depth() != CV_16U) {
    *why = "unsupported pixel depth (8- or 16-bit gray or colour images only)";
    return false;
  }
  // Percentiles from the histogram of the 65536 levels.
  std::vector<long> histogram(65536, 0);
  for (int r = 0; r < raw.rows; ++r) {
    const uint16_t* row = raw.ptr<uint16_t>(r);
    for (int c = 0; c < raw.cols; ++c) ++histogram[row[c]];
  }
  const double total = static_cast<double>(raw.total());
  auto percentile = [&](double p) {
    long seen = 0;
    for (int v = 0; v < 65536; ++v) {
      seen += histogram[v];
      if (seen >= p / 100.0 * total) return v;
    }
    return 65535;
  };
  const int lo = percentile(kLowPercentile);
  const int hi = std::max(lo + 1, percentile(kHighPercentile));
  raw.convertTo(*gray, CV_8U, 255.0 / (hi - lo), -255.0 * lo / (hi - lo));  // Saturating.
  char text[160];
  std::snprintf(text, sizeof(text), "16-bit, levels %d..%d (%.1f / %.1f %%iles) -> 0..255", lo, hi,
                kLowPercentile, kHighPercentile);
  *note = text;
  return true;
}

}  // namespace

bool ReadGray8(const std::string& path, GrayImage* image, std::string* why, std::string* note) {
  cv::Mat gray;
  *image = GrayImage();
  if (!ReadGray8Mat(path, &gray, why, note)) return false;
  image->width = gray.cols;
  image->height = gray.rows;
  image->pixels.resize(static_cast<size_t>(gray.cols) * gray.rows);
  for (int r = 0; r < gray.rows; ++r) {
    std::copy(gray.ptr<uint8_t>(r), gray.ptr<uint8_t>(r) + gray.cols,
              image->pixels.begin() + static_cast<size_t>(r) * gray.cols);
  }
  return true;
}

namespace {

// One image's outcome, computed on its own (in parallel, into its slot); sizes are compared after.
struct ImageOutcome {
  ImageResult result;
  View view;
  cv::Size size;  // Empty when unreadable.
  DetectionCounts counts;
};

// What one image contributes: a checkerboard's corners or the AprilGrid's tags, found (or taken
// from *found / *found_corners when `reuse`) and refined (through fit_camera when given).
struct ImageJob {
  const CalibrationTarget& target;
  const std::vector<Eigen::Vector3d>& grid_corners;  // AprilGrid: point id -> board point.
  FrameDetector* detector;                           // AprilGrid only.
  FoundTags* found;                                  // The image's tags (a cache slot or local).
  std::vector<Eigen::Vector2d>* found_corners;       // Checkerboard: the same for its corners.
  bool reuse;
  const CameraIntrinsics* fit_camera;
  LensFamily lens;  // The family the images will be calibrated with.
};
void ProcessImage(const fs::path& file, const ImageJob& job, ImageOutcome* out) {
  ImageResult& r = out->result;
  r.file = file.filename().string();
  cv::Mat gray;
  std::string note;
  ReadGray8Mat(file.string(), &gray, &r.reason, &note);
  if (gray.empty()) return;  // r.reason says why.
  out->size = gray.size();
  if (job.target.type != CalibrationTarget::Type::kAprilGrid) {
    if (!FindCheckerboard(gray, job.target, job.lens, job.fit_camera, job.reuse, job.found_corners,
                          &out->view, &r.reason)) {
      r.reason = "no " + std::to_string(job.target.cols) + "x" + std::to_string(job.target.rows) +
                 " checkerboard found";
    }
    return;
  }
  const GrayImageView image(gray.data, gray.cols, gray.rows, static_cast<int>(gray.step));
  if (!job.reuse) *job.found = job.detector->FindTags(image);
  for (const Observation& o :
       job.detector->RefineTags(image, *job.found, job.fit_camera, &out->counts)) {
    out->view.points.push_back(job.grid_corners[o.point_id]);
    out->view.pixels.push_back(o.pixel);
  }
  r.reason = std::to_string(out->counts.tags) + " tags" + (note.empty() ? "" : " (" + note + ")");
  if (out->counts.unknown_tags > 0) {
    r.reason += ", " + std::to_string(out->counts.unknown_tags) + " ids not on the grid";
  }
}

// The outcomes in file order: images of another size than the first readable one are refused,
// views with kMinViewPoints or more are used. Returns the image size (empty: none readable).
cv::Size CollectOutcomes(const CalibrationTarget& target, std::vector<ImageOutcome>* outcomes,
                         PointData* data, ImageFolderReport* report, std::vector<int>* used_index) {
  const bool aprilgrid = target.type == CalibrationTarget::Type::kAprilGrid;
  cv::Size size;
  for (ImageOutcome& out : *outcomes) {
    ImageResult& r = out.result;
    if (!out.size.empty() && size.empty()) size = out.size;
    if (!out.size.empty() && out.size != size) {
      r.reason = "size " + std::to_string(out.size.width) + "x" + std::to_string(out.size.height) +
                 " differs from the first image's " + std::to_string(size.width) + "x" +
                 std::to_string(size.height);
      out.view = View();
    } else if (aprilgrid && !out.size.empty()) {
      report->tags_detected += out.counts.tags;
      report->tags_possible += target.grid.NumTags();
      report->unknown_tags += out.counts.unknown_tags;
    }
    r.points = static_cast<int>(out.view.points.size());
    r.used = r.points >= static_cast<int>(kMinViewPoints);
    if (!r.used && r.points > 0) {  // Unreadable or mis-sized images have no points.
      r.reason += ": too few points (" + std::to_string(r.points) + " < " +
                  std::to_string(kMinViewPoints) + ")";
    }
    if (r.used) {
      data->views.push_back(std::move(out.view));
      data->view_names.push_back(r.file);
      used_index->push_back(static_cast<int>(report->images.size()));
      ++report->used;
    }
    report->images.push_back(r);
  }
  return size;
}

std::string TargetNotFound(const std::string& dir, size_t num_files,
                           const CalibrationTarget& target, const ImageFolderReport& report) {
  std::string why = dir + ": the target was found in none of " + std::to_string(num_files) +
                    " images (check the target YAML: type, size, family, spacing)";
  if (target.type == CalibrationTarget::Type::kAprilGrid) {
    char rate[160];
    std::snprintf(rate, sizeof(rate),
                  "; %ld of %ld possible tags detected (detection rate %.3f), %ld unknown ids",
                  report.tags_detected, report.tags_possible, report.DetectionRate(),
                  report.unknown_tags);
    why += rate;
  }
  return why;
}

}  // namespace

bool LoadImagePoints(const std::string& dir, const CalibrationTarget& target, PointData* data,
                     ImageFolderReport* report, std::vector<int>* used_index, std::string* why,
                     const ImagePointOptions& options) {
  std::vector<std::string> names;
  if (!ListImageFiles(dir, &names, why)) return false;
  if (!options.files.empty()) {
    const std::set<std::string> wanted(options.files.begin(), options.files.end());
    names.erase(std::remove_if(names.begin(), names.end(),
                               [&](const std::string& name) {
                                 return wanted.count(fs::path(name).filename().string()) == 0;
                               }),
                names.end());
    if (names.size() != wanted.size()) {
      if (why)
        *why = dir + ": " + std::to_string(wanted.size() - names.size()) +
               " of the images asked for are not image files of the folder";
      return false;
    }
  }
  const std::vector<fs::path> files(names.begin(), names.end());
  const bool aprilgrid = target.type == CalibrationTarget::Type::kAprilGrid;
  // One detector per worker (FrameDetector is not thread-safe).
  const int workers = ParallelWorkers(options.threads, files.size());
  std::vector<std::unique_ptr<FrameDetector>> detectors(aprilgrid ? workers : 0);
  for (std::unique_ptr<FrameDetector>& detector : detectors) {
    detector = FrameDetector::Create({target.grid}, ImageDetectorOptions(options), why);
    if (!detector) return false;
  }
  const std::vector<Eigen::Vector3d> grid_corners =
      aprilgrid ? target.grid.CornersInBoard() : std::vector<Eigen::Vector3d>();
  *data = PointData();
  data->format = aprilgrid ? "images+aprilgrid" : "images+checkerboard";
  *report = ImageFolderReport();
  used_index->clear();
  ImageDetectionCache* cache = options.detection_cache;
  const bool through_lens = aprilgrid && detectors[0]->FindingUsesCamera();
  // What the detection depends on: AprilTag 3 finds tags without the lens; a checkerboard's
  // detector order follows it (FindCheckerboard).
  const bool sector_based_first = !aprilgrid && options.lens != LensFamily::kRadTan;
  std::string source =
      dir + "\n" + TargetKey(target) + (sector_based_first ? "\nsector-based first" : "");
  for (const std::string& name : names) source += "\n" + name;
  // The same source holds the same files, one slot each.
  const bool reuse = cache && cache->filled && cache->source == source &&
                     (cache->found_through_lens || !through_lens);
  if (cache && !reuse) {
    *cache = ImageDetectionCache();
    cache->source = source;
    cache->per_image.resize(files.size());
    cache->checkerboard_corners.resize(files.size());
    cache->found_through_lens = through_lens;
  }
  const CameraIntrinsics* fit_camera = options.camera ? &*options.camera : nullptr;
  std::vector<ImageOutcome> outcomes(files.size());
  ParallelFor(files.size(), workers, [&](int worker, size_t f) {
    FoundTags found_here;  // Without a cache.
    std::vector<Eigen::Vector2d> corners_here;
    const ImageJob job{target,
                       grid_corners,
                       aprilgrid ? detectors[worker].get() : nullptr,
                       cache ? &cache->per_image[f] : &found_here,
                       cache ? &cache->checkerboard_corners[f] : &corners_here,
                       reuse,
                       fit_camera,
                       options.lens};
    ProcessImage(files[f], job, &outcomes[f]);
  });
  const cv::Size size = CollectOutcomes(target, &outcomes, data, report, used_index);
  if (cache) cache->filled = true;
  data->image_width = size.width;
  data->image_height = size.height;
  if (report->used == 0) {
    if (why) *why = TargetNotFound(dir, files.size(), target, *report);
    return false;
  }
  return true;
}

}  // namespace calibench
