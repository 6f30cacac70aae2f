// A calibrated camera as calibrate returns it and a camera file holds it (io/camera_io.h reads and
// writes it as OpenCV, Kalibr and mrcal files): the intrinsics, their standard deviations, the
// image size, the fit's reprojection RMS, the lens model it was estimated with and the covariance
// of its projection (batch/projection_uncertainty.h).
#pragma once

#include <string>
#include <vector>

#include "batch/projection_uncertainty.h"
#include "camera/camera.h"

namespace calibench {

struct CameraFile {
  CameraIntrinsics intrinsics;
  IntrinsicsArray intrinsics_std{};  // Raw order, phi in radians (written as std_phi_deg); NaN:
                                     // fixed or unknown. Only the opencv format keeps them.
  int image_width = 0, image_height = 0;
  double rms_reproj_px = 0.0;
  std::vector<double> view_rms_px;
  LensModel lens_model = LensModel::kPinholeK2;  // The model it was estimated with.
  bool estimate_skew = false;
  // Cov(z) of the quoted projection uncertainty (calib/calibration_uncertainty.h): unset
  // (num_views 0) when the file carries none. Only the opencv format keeps it.
  ProjectionCovariance projection;
  double projection_scale = 1.0;  // The jackknife's scale already applied to it (>= 1).
  // "jackknife": the scale comes from a leave-one-view-out spread; "formal": none was computed
  // (too many views, --jackknife off): on real images the figure is then usually too small.
  std::string projection_source = "formal";
  // e.g. "pinhole-k2" or "pinhole-k2+skew".
  std::string ModelName() const {
    return std::string(ToString(lens_model)) + (estimate_skew ? "+skew" : "");
  }
};

}  // namespace calibench
