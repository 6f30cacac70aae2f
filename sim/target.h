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

#include "camera/pose.h"

namespace calibench {

// The most corners a board may have along a side (an index of a corner stays far inside int).
constexpr int kMaxCornersPerSide = 10000;

struct PlanarBoard {
  int rows = 6, cols = 8;    // Corners.
  double spacing_m = 0.1;    // Corner pitch.
  Rigid3 points_from_board;  // Board pose in the points frame.

  int NumCorners() const { return rows * cols; }
  std::vector<Eigen::Vector3d> CornersInBoard() const;
  std::vector<Eigen::Vector3d> CornersInPointsFrame() const;
  // 2 .. kMaxCornersPerSide corners a side, a positive spacing, a rotation.
  bool Check(std::string* why) const;
};

// An AprilTag grid as Kalibr defines its aprilgrid (GridCalibrationTargetAprilgrid.cpp and
// kalibr_create_target_pdf, read for this): tag_rows x tag_cols tags.
//   tag_size_m (Kalibr's tagSize): the edge of a tag's black square, border bits included — the
//     square whose corners the detector reports (for a 2-bit border: the outer edge of the two
//     black rings; the data bits are the middle 6 of 10 cells for tag36h11).
//   tag_spacing (Kalibr's tagSpacing): the white gap between two tags' black squares as a fraction
//     of tag_size_m; the corner pitch from one tag to the next is p = s (1 + tag_spacing).
//   black_tag_border (Kalibr's blackTagBorder): border width in bits, 1 (AprilTag 3's own layout,
//     and the default here for scenarios) or 2 (Kalibr's printed grids; tag_family.h).
// Board frame: x right, y up, z out of the board (Kalibr's). Tag (r, c) — r counted upwards from
// the bottom row, c rightwards — has id first_id + r * tag_cols + c (id 0 bottom-left, as
// Kalibr's generator draws it and its detector numbers it); its black square spans
// [c p, c p + s] x [r p, r p + s]. Corner order per tag = Kalibr's and the detector's:
// bottom-left, bottom-right, top-right, top-left in the board frame (= of the tag's bitmap, placed
// bitmap-up = board +y); corner k of the tag with index i (= id - first_id) is point 4 i + k.
// (Kalibr numbers the same corners row-major on a 2 tag_rows x 2 tag_cols grid; the positions
// are identical.)
//   corner_squares (Kalibr's printed grids, kalibr_create_target_pdf): black squares of edge
//     g = tag_spacing * s filling every gap crossing, (tag_cols + 1) x (tag_rows + 1) of them:
//     square (i, j), i = 0..tag_cols, j = 0..tag_rows, spans [i p - g, i p] x [j p - g, j p]. They
//     touch the tags' corners, so each tag corner is an X-junction; they carry no points. The board
//     (renderer) is then white to 2 g around the tags (g beyond the outer squares), else to g.
struct AprilGrid {
  std::string family = "tag36h11";
  int tag_rows = 6, tag_cols = 6;
  double tag_size_m = 0.088;
  double tag_spacing = 0.3;
  int first_id = 0;
  int black_tag_border = 1;     // Border bits: 1 (AprilTag 3) or 2 (Kalibr's printed grids).
  bool corner_squares = false;  // Kalibr's black squares at the tag corners (above).
  Rigid3 points_from_board;

  int NumTags() const { return tag_rows * tag_cols; }
  double Pitch() const { return tag_size_m * (1.0 + tag_spacing); }
  std::vector<Eigen::Vector3d> CornersInBoard() const;
  std::vector<Eigen::Vector3d> CornersInPointsFrame() const;
  // A known family whose codes hold every id (first_id .. first_id + NumTags() - 1), positive
  // sizes, a border of 1 or 2 bits, a rotation.
  bool Check(std::string* why) const;
};

// A planar board of a scenario's point set as the batch methods see it: its corners in the board
// frame (z = 0), where the board sits in the points frame, and the index of its first corner among
// the scenario's points (boards follow each other: board b has points first_point ..).
struct BoardLayout {
  std::vector<Eigen::Vector3d> corners_in_board;
  Rigid3 points_from_board;
  int first_point = 0;
};

bool operator==(const PlanarBoard& a, const PlanarBoard& b);
bool operator==(const AprilGrid& a, const AprilGrid& b);

// Corners of every board of a rig, board after board.
std::vector<Eigen::Vector3d> RigCorners(const std::vector<PlanarBoard>& rig);

}  // namespace calibench
