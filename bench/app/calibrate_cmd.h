// `calibench calibrate`: a camera from point files (--points) or from a folder of images of a
// target (--images, calib/image_points.h), optionally from or against a given camera (--init,
// --evaluate), or with the lens model chosen (--model auto): the flags into calib/'s options,
// calib/calibrate_report.h's text on stdout, the camera file written by io/camera_io.h.
#pragma once

#include <string>
#include <vector>

namespace calibench {

struct CalibrateArgs {
  std::string points_path, target_path, init_path, format;
  // One --images per camera: a folder or a quoted glob ('dir/left*.jpg'). Two or more: a rig
  // (calib/calibrate_rig.h), its images paired by the number or stem in their names.
  std::vector<std::string> images;
  std::string out_path = "camera.yaml", model = "pinhole-k2";
  bool skew = false, model_given = false, out_given = false, evaluate = false;
  bool no_tag_prediction = false;  // Keep only the tags AprilTag 3 decodes.
  int corner_iterations = 4;       // Re-fits of the corners through the estimate (aprilgrid, lens).
  int threads = 0;                 // Images read and detected in parallel (0: every core).
  std::string corner_refinement;   // Empty: the default (photometric; see ImagePointOptions).
  std::string jackknife = "auto";  // auto | on | off (CalibrateOptions::Jackknife).
  bool cross_validate = false;     // Also calibrate two halves of the views and compare them.
  bool no_page = false;            // No page of figures beside the camera file.
  // A rig of two cameras or more: the rectified first pair written as one PNG (empty: beside
  // --out, <out stem>-rectified.png, for the first two cameras).
  std::string rectified_path;
};

// 0 on success; 2 with a message for bad arguments or input; 3 when the camera file cannot be
// written; 4 when no usable calibration came out.
int Calibrate(const CalibrateArgs& args);
// The same for a rig (two --images or more; calibrate_rig_cmd.cc): the rig's files, its report
// and the rectified pair.
int CalibrateRig(const CalibrateArgs& args);

// The lens model names, comma-separated (for help and error texts).
std::string LensModelList();

}  // namespace calibench
