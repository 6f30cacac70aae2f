#include "core/target.h"

#include <cmath>

namespace calibench {

std::vector<Eigen::Vector3d> PlanarBoard::CornersInBoard() const {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(NumCorners());
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) corners.emplace_back(c * spacing_m, r * spacing_m, 0.0);
  }
  return corners;
}

std::vector<Eigen::Vector3d> PlanarBoard::CornersInPointsFrame() const {
  std::vector<Eigen::Vector3d> corners = CornersInBoard();
  for (Eigen::Vector3d& p : corners) p = points_from_board * p;
  return corners;
}

bool PlanarBoard::Check(std::string* why) const {
  std::string msg;
  if (rows < 2 || cols < 2) msg = "a board needs at least 2 x 2 corners";
  if (!(spacing_m > 0 && std::isfinite(spacing_m))) msg = "spacing_m must be positive";
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

}  // namespace calibench
