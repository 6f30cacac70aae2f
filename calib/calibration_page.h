// The page a user reads beside a camera file that `calibrate` wrote: CAMERA.md and its figures
// (calib/calibration_pictures.h), named after the camera file's stem:
//   STEM-uncertainty.png    the quoted projection uncertainty over the image (rays at infinity,
//                           calib/calibration_uncertainty.h) with contours and the corners used;
//   STEM-residuals.png      each corner's residual (measured - projected) as a vector;
//   STEM-view-residuals.png the residuals' distribution per view (views that disagree stand out);
//   STEM-coverage.png       where the corners fell in the image, per view, and the share of the
//                           image's 10 x 10 cells they cover.
//   STEM-cross-validation.png  with a cross-validation (calib/cross_validate.h): the projection
//                           difference of the two halves' calibrations.
// The Markdown gives the numbers the figures show (uncertainty at the centre, median and worst,
// formal against jackknife, coverage, RMS) and links the figures by relative path. Every file is
// written atomically; a failure names the file.
#pragma once

#include <string>
#include <vector>

#include "calib/calibrate_camera.h"
#include "calib/calibrate_rig.h"
#include "calib/cross_validate.h"

namespace calibench {

struct CalibrationPageFiles {
  std::string markdown;
  std::vector<std::string> figures;
};

// The page of a usable `result` whose camera was written to `camera_path`. False with *why
// naming the file that could not be written.
// `cross_validation` may be null.
bool WriteCalibrationPage(const std::string& camera_path, const CalibrateResult& result,
                          const CrossValidation* cross_validation, CalibrationPageFiles* files,
                          std::string* why);

// A rig's page beside its file `rig_path` (calib/calibrate_rig.h): per camera the formal
// projection uncertainty of the joint solve (RigRefineResult::projection, the frame of the frames
// it saw), its joint residuals and its coverage; the baselines and relative rotations with their
// std; the epipolar error per pair; the rectified pair when `rectified_png` names one (linked).
bool WriteRigCalibrationPage(const std::string& rig_path, const CalibrateRigResult& result,
                             const std::string& rectified_png, CalibrationPageFiles* files,
                             std::string* why);

// The residuals (measured - projected, px) of `result`'s used views at its fit, per used view, and
// those views' pixels and names.
struct ViewResiduals {
  std::vector<std::string> names;
  std::vector<std::vector<Eigen::Vector2d>> pixels, residuals_px;
};
ViewResiduals ResidualsOf(const CalibrateResult& result);

}  // namespace calibench
