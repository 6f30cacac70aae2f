// A rendered test rig: two 4 x 5 tag36h11 AprilGrids 45 degrees apart seen by a moving camera
// (tests of the rendered source and of the diagnostics that decorate it).
#pragma once

#include <vector>

#include "sim/scene.h"
#include "sim/target.h"

namespace calibench {

// Two 4 x 5 tag36h11 grids 45 degrees apart, 2.5 m in front of a camera looking along world +y
// (the thesis camera 1 orientation, no skew), the body swaying slowly.
struct Rig {
  std::vector<AprilGrid> grids;
  SceneTruth scene;
};

inline Rig MakeRig(double duration_s) {
  Rig rig;
  AprilGrid a;
  a.tag_rows = 4, a.tag_cols = 5, a.tag_size_m = 0.1;
  a.points_from_board = {FromRollPitchYawDeg({90, 0, 0}), {-0.55, 0.2, 0.1}};
  AprilGrid b = a;
  b.first_id = 20;
  b.points_from_board = {FromRollPitchYawDeg({90, 0, 45}), {0.15, 0.2, 0.1}};
  rig.grids = {a, b};
  SceneTruth& s = rig.scene;
  s.calibration_case = CalibrationCase::kMovingCamera;
  s.intrinsics = {822, 813, 90, 321, 239};
  Eigen::Matrix3d r_c;
  r_c << -1, 0, 0, 0, 0, 1, 0, 1, 0;
  s.parent_from_cam = {r_c, {0.4, -2.3, 0.47}};
  for (const AprilGrid& g : rig.grids) {
    const std::vector<Eigen::Vector3d> c = g.CornersInPointsFrame();
    s.points.insert(s.points.end(), c.begin(), c.end());
  }
  TwistProfile sway;
  sway.w_sin = {0.02, 0.0, 0.03};
  sway.frequency_rad_s = 2.0;
  Motion::Options motion_options;
  motion_options.duration_s = duration_s;
  s.motion = Motion(sway, motion_options);
  s.duration_s = duration_s;
  return rig;
}

}  // namespace calibench
