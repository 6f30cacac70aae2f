#include "sim/target.h"

#include <cmath>
#include <cstdint>

#include "sim/tag_family.h"

namespace calibench {
namespace {

std::vector<Eigen::Vector3d> Transformed(const Rigid3& b_from_a,
                                         std::vector<Eigen::Vector3d> points) {
  for (Eigen::Vector3d& p : points) p = b_from_a * p;
  return points;
}

}  // namespace

std::vector<Eigen::Vector3d> PlanarBoard::CornersInBoard() const {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(NumCorners());
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) corners.emplace_back(c * spacing_m, r * spacing_m, 0.0);
  }
  return corners;
}

std::vector<Eigen::Vector3d> PlanarBoard::CornersInPointsFrame() const {
  return Transformed(points_from_board, CornersInBoard());
}

bool PlanarBoard::Check(std::string* why) const {
  std::string msg;
  if (rows < 2 || cols < 2) msg = "a board needs at least 2 x 2 corners";
  if (rows > kMaxCornersPerSide || cols > kMaxCornersPerSide) {
    msg = "a board has at most " + std::to_string(kMaxCornersPerSide) + " corners a side";
  }
  if (!(spacing_m > 0 && std::isfinite(spacing_m))) msg = "spacing_m must be positive";
  if (!CheckRotation(points_from_board.rotation, 1e-9, false, nullptr)) msg = "invalid rotation";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

std::vector<Eigen::Vector3d> AprilGrid::CornersInBoard() const {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(4 * NumTags());
  const double p = Pitch(), s = tag_size_m;
  for (int r = 0; r < tag_rows; ++r) {
    for (int c = 0; c < tag_cols; ++c) {
      const double x = c * p, y = r * p;
      corners.emplace_back(x, y, 0.0);
      corners.emplace_back(x + s, y, 0.0);
      corners.emplace_back(x + s, y + s, 0.0);
      corners.emplace_back(x, y + s, 0.0);
    }
  }
  return corners;
}

std::vector<Eigen::Vector3d> AprilGrid::CornersInPointsFrame() const {
  return Transformed(points_from_board, CornersInBoard());
}

bool AprilGrid::Check(std::string* why) const {
  std::string msg;
  if (tag_rows < 1 || tag_cols < 1) msg = "an aprilgrid needs at least one tag";
  if (!(tag_size_m > 0 && std::isfinite(tag_size_m))) msg = "tag_size_m must be positive";
  if (!(tag_spacing > 0 && std::isfinite(tag_spacing))) msg = "tag_spacing must be positive";
  if (first_id < 0) msg = "first_id must be >= 0";
  const int codes = NumAprilTagCodes(family);
  const int64_t ids_end =
      static_cast<int64_t>(first_id) + static_cast<int64_t>(tag_rows) * tag_cols;  // No overflow.
  if (codes == 0) {
    msg = "unknown AprilTag family '" + family + "'";
  } else if (tag_rows >= 1 && tag_cols >= 1 && first_id >= 0 && ids_end > codes) {
    msg = family + " has " + std::to_string(codes) + " codes (ids 0.." + std::to_string(codes - 1) +
          "): " + std::to_string(tag_rows) + " x " + std::to_string(tag_cols) + " tags from id " +
          std::to_string(first_id) + " need ids up to " + std::to_string(ids_end - 1);
  }
  if (black_tag_border != 1 && black_tag_border != 2) {
    msg = "black_tag_border must be 1 (AprilTag 3) or 2 (Kalibr), not " +
          std::to_string(black_tag_border);
  }
  if (!CheckRotation(points_from_board.rotation, 1e-9, false, nullptr)) msg = "invalid rotation";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

std::vector<Eigen::Vector3d> RigCorners(const std::vector<PlanarBoard>& rig) {
  std::vector<Eigen::Vector3d> corners;
  for (const PlanarBoard& b : rig) {
    const std::vector<Eigen::Vector3d> c = b.CornersInPointsFrame();
    corners.insert(corners.end(), c.begin(), c.end());
  }
  return corners;
}

bool operator==(const PlanarBoard& a, const PlanarBoard& b) {
  return a.rows == b.rows && a.cols == b.cols && a.spacing_m == b.spacing_m &&
         a.points_from_board == b.points_from_board;
}

bool operator==(const AprilGrid& a, const AprilGrid& b) {
  return a.family == b.family && a.tag_rows == b.tag_rows && a.tag_cols == b.tag_cols &&
         a.tag_size_m == b.tag_size_m && a.tag_spacing == b.tag_spacing &&
         a.first_id == b.first_id && a.black_tag_border == b.black_tag_border &&
         a.corner_squares == b.corner_squares && a.points_from_board == b.points_from_board;
}

}  // namespace calibench
