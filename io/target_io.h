// Calibration targets described by Kalibr's target YAML (the format Kalibr's
// kalibr_calibrate_cameras reads), for `calibench calibrate --images`:
//   target_type: 'aprilgrid'                target_type: 'checkerboard'
//   tagCols: 6                              targetCols: 9          # inner corners per row
//   tagRows: 6                              targetRows: 6          # inner corners per column
//   tagSize: 0.088        # m               rowSpacingMeters: 0.025
//   tagSpacing: 0.3       # fraction        colSpacingMeters: 0.025
//   tagFamily: tag36h11   # calibench extension, optional (Kalibr: always tag36h11)
//   blackTagBorder: 2     # optional: border bits, 1 or 2 (default 2 as Kalibr's detector
//                         # option; 1 for the families with a white border, which have no other)
//   cornerSquares: true   # calibench extension, optional: the black squares Kalibr's generator
//                         # draws at the tags' corners (AprilGrid::corner_squares; default true,
//                         # as every Kalibr grid has them; false for a grid without them)
// tagSize, tagSpacing, corner order and ids mean exactly what they mean to Kalibr (sim/target.h).
// Errors name the file, line, column, field and reason.
#pragma once

#include <string>

#include "calib/calibration_target.h"

namespace calibench {

bool LoadTargetYaml(const std::string& path, CalibrationTarget* target, std::string* why);
// The Kalibr target YAML of `target` (every field explicit; LoadTargetYamlFromString reads it
// back to an equal target).
std::string TargetYamlText(const CalibrationTarget& target);
// LoadTargetYaml from YAML text (`path` names it in messages).
bool LoadTargetYamlFromString(const std::string& yaml, const std::string& path,
                              CalibrationTarget* target, std::string* why);

}  // namespace calibench
