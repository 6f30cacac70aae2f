#include "detect/chessboard.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "util/opencv_threads.h"

namespace calibench {

bool ChessboardOptions::Check(std::string* why) const {
  if (cols >= 2 && rows >= 2) return true;
  if (why) *why = "a checkerboard needs at least 2 x 2 inner corners";
  return false;
}

namespace {

// The mean gray of a square of the grid, the one whose corners are (r, c), (r, c + 1), (r + 1, c)
// and (r + 1, c + 1): bilinear samples at its centre and halfway from it to each corner.
double SquareGray(const cv::Mat& image, const std::vector<Eigen::Vector2d>& corners, int cols,
                  int r, int c) {
  const Eigen::Vector2d quad[4] = {corners[r * cols + c], corners[r * cols + c + 1],
                                   corners[(r + 1) * cols + c + 1], corners[(r + 1) * cols + c]};
  const Eigen::Vector2d centre = (quad[0] + quad[1] + quad[2] + quad[3]) / 4;
  double sum = 0;
  int n = 0;
  for (int k = -1; k < 4; ++k) {
    const Eigen::Vector2d p = k < 0 ? centre : 0.5 * (centre + quad[k]);
    const double x = std::clamp(p.x(), 0.0, image.cols - 1.001);
    const double y = std::clamp(p.y(), 0.0, image.rows - 1.001);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const double fx = x - x0, fy = y - y0;
    sum += (1 - fy) * ((1 - fx) * image.at<uint8_t>(y0, x0) + fx * image.at<uint8_t>(y0, x0 + 1)) +
           fy * ((1 - fx) * image.at<uint8_t>(y0 + 1, x0) + fx * image.at<uint8_t>(y0 + 1, x0 + 1));
    ++n;
  }
  return sum / n;
}

// The detectors' orderings differ (the classic search and the sector-based one may start at
// opposite ends, or walk the rows the other way): one order for every camera and detector, so that
// the cameras of a rig agree on the board frame. (1) Seen from the front, corner (0, 1) - (0, 0)
// and (1, 0) - (0, 0) turn as the image's x and y do (board z away from the camera); else the
// rows are reversed. (2) When cols + rows is odd, a half turn swaps the dark and light squares at
// the origin: the square between corners (0, 0) and (1, 1) is made the dark one (as
// sim/checkerboard_image.h draws it). A board with cols + rows even keeps its half-turn ambiguity.
void CanonicalOrder(const cv::Mat& image, int cols, int rows, std::vector<Eigen::Vector2d>* c) {
  const Eigen::Vector2d along_row = (*c)[1] - (*c)[0], along_col = (*c)[cols] - (*c)[0];
  if (along_row.x() * along_col.y() - along_row.y() * along_col.x() < 0) {
    std::vector<Eigen::Vector2d> flipped(c->size());
    for (int r = 0; r < rows; ++r) {
      for (int k = 0; k < cols; ++k) flipped[r * cols + k] = (*c)[(rows - 1 - r) * cols + k];
    }
    *c = flipped;
  }
  if ((cols + rows) % 2 == 0) return;
  // The origin's square against its neighbour along the row (or the column, on a 2-wide board).
  const double origin = SquareGray(image, *c, cols, 0, 0);
  const double neighbour =
      cols >= 3 ? SquareGray(image, *c, cols, 0, 1) : SquareGray(image, *c, cols, 1, 0);
  if (origin > neighbour) std::reverse(c->begin(), c->end());
}

}  // namespace

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
  CanonicalOrder(image, options.cols, options.rows, corners);
  return true;
}

}  // namespace calibench
