#include "calib/detect_images.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "calib/image_points.h"
#include "detect/chessboard.h"

namespace calibench {

bool DetectImageCorners(const std::string& dir, const CalibrationTarget& target,
                        std::vector<ImageCorners>* images, std::string* why) {
  images->clear();
  const bool checkerboard = target.type == CalibrationTarget::Type::kCheckerboard;
  std::vector<std::string> files;
  if (!ListImageFiles(dir, &files, why)) return false;
  std::unique_ptr<FrameDetector> detector;
  if (!checkerboard) {
    detector = FrameDetector::Create({target.grid}, ImageDetectorOptions(), why);
    if (!detector) return false;
  }
  ChessboardOptions chessboard;
  chessboard.cols = target.cols;
  chessboard.rows = target.rows;
  for (const std::string& path : files) {
    ImageCorners image;
    image.file = std::filesystem::path(path).filename().string();
    GrayImage gray;
    std::string note;
    image.readable = ReadGray8(path, &gray, &image.note, &note);
    if (image.readable && checkerboard) {
      image.note = note;
      std::vector<Eigen::Vector2d> corners;
      std::string how;
      if (FindChessboardCorners(gray, chessboard, &corners, &how)) {
        image.tags = 1;
        for (size_t k = 0; k < corners.size(); ++k) {
          image.corners.push_back({-1, static_cast<int>(k), corners[k].x(), corners[k].y()});
        }
      }
    } else if (image.readable) {
      image.note = note;
      DetectionCounts counts;
      for (const Observation& o : detector->Detect(gray, &counts)) {
        // Point 4 i + k is corner k of the tag with index i = id - first_id (target.h).
        image.corners.push_back({target.grid.first_id + o.point_id / 4, o.point_id % 4, o.pixel.x(),
                                 o.pixel.y(), o.crlb_px});
      }
      image.refused_tags = counts.RefusedTags();
      image.refused_reasons = FormatFitFailures(counts.refused_tags);
      image.tags = counts.tags;
      image.unknown_tags = counts.unknown_tags;
      image.border_tags = counts.border_tags;
      image.duplicate_tags = counts.duplicate_tags;
      image.unrefined_copy_tags = counts.unrefined_copy_tags;
      image.predicted_tags = counts.predicted_tags;
      image.refitted_tags = counts.refitted_tags;
      image.refused_predictions = counts.refused_predictions;
      image.covered_tags = counts.covered_tags;
    }
    images->push_back(std::move(image));
  }
  return true;
}

std::string FormatImageCorners(const std::vector<ImageCorners>& images,
                               const CalibrationTarget& target) {
  const bool checkerboard = target.type == CalibrationTarget::Type::kCheckerboard;
  std::ostringstream out;
  char line[512];
  long tags = 0, corners = 0;
  for (const ImageCorners& image : images) {
    if (!image.readable) {
      std::snprintf(line, sizeof(line), "%-30s skipped: %s\n", image.file.c_str(),
                    image.note.c_str());
      out << line;
      continue;
    }
    std::string extra;
    if (image.unknown_tags > 0)
      extra += ", " + std::to_string(image.unknown_tags) + " ids not on the grid";
    if (image.border_tags > 0)
      extra += ", " + std::to_string(image.border_tags) + " at the image border (dropped)";
    if (image.refused_tags > 0) {
      extra += ", " + std::to_string(image.refused_tags) + " refused by the photometric fit (" +
               image.refused_reasons + ")";
    }
    if (image.unrefined_copy_tags > 0) {
      extra += ", " + std::to_string(image.unrefined_copy_tags) +
               " behind corner squares not refined (dropped)";
    }
    if (image.predicted_tags > 0) {
      extra += ", " + std::to_string(image.predicted_tags) +
               " of them not decoded but fitted where their neighbours put them";
    }
    if (image.refitted_tags > 0) {
      extra += ", " + std::to_string(image.refitted_tags) +
               " of them refused from AprilTag 3's corners but fitted where their neighbours put "
               "them";
    }
    if (image.covered_tags > 0) {
      extra += ", " + std::to_string(image.covered_tags) +
               " of them fitted without pixels that disagree with their pattern (covered in part)";
    }
    if (image.refused_predictions > 0) {
      extra += ", " + std::to_string(image.refused_predictions) +
               " predicted tags the pixels did not show (dropped)";
    }
    if (image.duplicate_tags > 0)
      extra += ", " + std::to_string(image.duplicate_tags) + " duplicate ids (dropped)";
    if (!image.note.empty()) extra += "; " + image.note;
    if (checkerboard) {
      std::snprintf(line, sizeof(line), "%-30s %3zu of %d corners%s\n", image.file.c_str(),
                    image.corners.size(), target.cols * target.rows, extra.c_str());
    } else {
      std::snprintf(line, sizeof(line), "%-30s %3d of %d tags%s\n", image.file.c_str(), image.tags,
                    target.grid.NumTags(), extra.c_str());
    }
    out << line;
    tags += image.tags;
    corners += static_cast<long>(image.corners.size());
  }
  out << images.size() << " images, " << tags << (checkerboard ? " boards, " : " tags, ") << corners
      << " corners\n";
  return out.str();
}

}  // namespace calibench
