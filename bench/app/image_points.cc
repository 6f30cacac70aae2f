#include "bench/app/image_points.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "detect/chessboard.h"
#include "detect/frame_detector.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

// A view needs this many points: more than a homography's 4, so that a view says something.
constexpr size_t kMinViewPoints = 8;

bool IsImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp"}) {
    if (ext == e) return true;
  }
  return false;
}

// The checkerboard's corners (detect/chessboard.h) with their board points: corner (r, c) of the
// targetCols x targetRows inner corners is at (c * colSpacing, r * rowSpacing, 0).
bool FindCheckerboard(const cv::Mat& gray, const CalibrationTarget& t, View* view,
                      std::string* how) {
  ChessboardOptions options;
  options.cols = t.cols;
  options.rows = t.rows;
  std::vector<Eigen::Vector2d> corners;
  const GrayImageView image(gray.data, gray.cols, gray.rows, static_cast<int>(gray.step));
  if (!FindChessboardCorners(image, options, &corners, how)) return false;
  for (int r = 0; r < t.rows; ++r) {
    for (int c = 0; c < t.cols; ++c) {
      view->points.emplace_back(c * t.col_spacing_m, r * t.row_spacing_m, 0.0);
      view->pixels.push_back(corners[r * t.cols + c]);
    }
  }
  return true;
}

}  // namespace

bool LoadImagePoints(const std::string& dir, const CalibrationTarget& target, PointData* data,
                     ImageFolderReport* report, std::vector<int>* used_index, std::string* why) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file() && IsImageFile(it->path())) files.push_back(it->path());
  }
  if (ec) {
    if (why) *why = dir + ": cannot list the folder: " + ec.message();
    return false;
  }
  if (files.empty()) {
    if (why) *why = dir + ": no images (png, jpg, jpeg, tif, tiff, bmp) in the folder";
    return false;
  }
  std::sort(files.begin(), files.end());
  std::unique_ptr<FrameDetector> detector;
  std::vector<Eigen::Vector3d> grid_corners;
  if (target.type == CalibrationTarget::Type::kAprilGrid) {
    detector = FrameDetector::Create({target.grid}, FrameDetectorOptions(), why);
    if (!detector) return false;
    grid_corners = target.grid.CornersInBoard();
  }
  *data = PointData();
  data->format = target.type == CalibrationTarget::Type::kAprilGrid ? "images+aprilgrid"
                                                                    : "images+checkerboard";
  *report = ImageFolderReport();
  used_index->clear();
  cv::Size size;
  for (const fs::path& file : files) {
    ImageResult r;
    r.file = file.filename().string();
    cv::Mat gray;
    try {
      gray = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    } catch (const cv::Exception& e) {
      gray.release();
    }
    View view;
    if (gray.empty()) {
      std::error_code size_ec;
      const auto bytes = fs::file_size(file, size_ec);
      r.reason = size_ec      ? "unreadable: " + size_ec.message()
                 : bytes == 0 ? "unreadable: empty file (0 bytes)"
                              : "unreadable: cannot be decoded (not an image, or truncated)";
    } else if (!size.empty() && gray.size() != size) {
      r.reason = "size " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) +
                 " differs from the first image's " + std::to_string(size.width) + "x" +
                 std::to_string(size.height);
    } else if (target.type == CalibrationTarget::Type::kCheckerboard) {
      if (!FindCheckerboard(gray, target, &view, &r.reason)) {
        r.reason = "no " + std::to_string(target.cols) + "x" + std::to_string(target.rows) +
                   " checkerboard found";
      }
    } else {
      DetectionCounts counts;
      for (const Observation& o : detector->Detect(gray.data, gray.cols, gray.rows,
                                                   static_cast<int>(gray.step), &counts)) {
        view.points.push_back(grid_corners[o.point_id]);
        view.pixels.push_back(o.pixel);
      }
      report->tags_detected += counts.tags;
      report->tags_possible += target.grid.NumTags();
      report->unknown_tags += counts.unknown_tags;
      r.reason = std::to_string(counts.tags) + " tags";
      if (counts.unknown_tags > 0) {
        r.reason += ", " + std::to_string(counts.unknown_tags) + " ids not on the grid";
      }
    }
    if (!gray.empty() && size.empty()) size = gray.size();
    r.points = static_cast<int>(view.points.size());
    r.used = r.points >= static_cast<int>(kMinViewPoints);
    if (!r.used && r.points > 0) {  // Unreadable or mis-sized images have no points.
      r.reason += ": too few points (" + std::to_string(r.points) + " < " +
                  std::to_string(kMinViewPoints) + ")";
    }
    if (r.used) {
      data->views.push_back(std::move(view));
      used_index->push_back(static_cast<int>(report->images.size()));
      ++report->used;
    }
    report->images.push_back(r);
  }
  data->image_width = size.width;
  data->image_height = size.height;
  if (report->used == 0) {
    if (why) {
      *why = dir + ": the target was found in none of " + std::to_string(files.size()) +
             " images (check the target YAML: type, size, family, spacing)";
      if (target.type == CalibrationTarget::Type::kAprilGrid) {
        char rate[160];
        std::snprintf(rate, sizeof(rate),
                      "; %ld of %ld possible tags detected (detection rate %.3f), %ld unknown ids",
                      report->tags_detected, report->tags_possible, report->DetectionRate(),
                      report->unknown_tags);
        *why += rate;
      }
    }
    return false;
  }
  return true;
}

}  // namespace calibench
