#include "detect/chessboard.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "util/opencv_threads.h"

namespace calibench {

bool ChessboardOptions::Check(std::string* why) const {
  if (cols >= 2 && rows >= 2) return true;
  if (why) *why = "a checkerboard needs at least 2 x 2 inner corners";
  return false;
}

bool FindChessboardCorners(const GrayImageView& gray, const ChessboardOptions& options,
                           std::vector<Eigen::Vector2d>* corners, std::string* how) {
  corners->clear();
  if (!options.Check(how)) return false;
  UseSequentialOpenCv();  // Over images in parallel instead (util/opencv_threads.h).
  // A view, not a copy: OpenCV only reads it.
  const cv::Mat image(gray.height, gray.width, CV_8UC1, const_cast<uint8_t*>(gray.data),
                      static_cast<size_t>(gray.stride));
  const cv::Size pattern(options.cols, options.rows);
  std::vector<cv::Point2f> found_corners;
  auto classic = [&] {
    if (!cv::findChessboardCorners(image, pattern, found_corners,
                                   cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE |
                                       cv::CALIB_CB_FAST_CHECK)) {
      return false;
    }
    cv::cornerSubPix(image, found_corners, cv::Size(5, 5), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.1));
    *how = "findChessboardCorners + cornerSubPix";
    return true;
  };
  auto sector_based = [&] {
    *how = "findChessboardCornersSB";
    return cv::findChessboardCornersSB(image, pattern, found_corners);
  };
  const bool found =
      options.sector_based_first ? sector_based() || classic() : classic() || sector_based();
  const size_t expected = static_cast<size_t>(options.cols) * static_cast<size_t>(options.rows);
  if (!found || found_corners.size() != expected) return false;
  for (const cv::Point2f& p : found_corners) corners->emplace_back(p.x, p.y);
  return true;
}

}  // namespace calibench
