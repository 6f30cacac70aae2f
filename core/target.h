// Calibration targets: planar boards of corners, alone or as rigs of several boards at angles
// (so that the pooled points are not coplanar).
//
// A board's corners lie on z = 0 of its own frame, row by row: corner (r, c) is at
// (c * spacing, r * spacing, 0). `points_from_board` places the board in the frame the scenario's
// points live in (the body for a fixed camera, the world for a moving camera; see scene.h).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/pose.h"

namespace calibench {

struct PlanarBoard {
  int rows = 6, cols = 8;    // Corners.
  double spacing_m = 0.1;    // Corner pitch.
  Rigid3 points_from_board;  // Board pose in the points frame.

  int NumCorners() const { return rows * cols; }
  std::vector<Eigen::Vector3d> CornersInBoard() const;
  std::vector<Eigen::Vector3d> CornersInPointsFrame() const;
  bool Check(std::string* why) const;
};

// Corners of every board of a rig, board after board.
std::vector<Eigen::Vector3d> RigCorners(const std::vector<PlanarBoard>& rig);

}  // namespace calibench
