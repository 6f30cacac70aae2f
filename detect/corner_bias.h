// The corner error of the rendered pipeline (core/render.h -> AprilTag 3 -> corner refinement)
// against the exact projections, split into its bias and its noise (`calibench corner-bias`).
//
// One case is one view of a single tag36h11 tag (a 1 x 1 AprilGrid on its white board) by an ideal
// pinhole camera: the tag's centre projects to `centre_px`, its black square spans `tag_px` pixels
// (at the centre's depth), and the board is tilted by `tilt_deg` about the board's x axis (the
// viewing angle: 0 = fronto-parallel) after an in-plane rotation `roll_deg`. The case is seen in
// `views` views, each shifted by a random sub-pixel offset (uniform in [-0.5, 0.5] px) and
// rendered `draws` times with independent gray noise; per view v, draw d and corner k (detector
// order: bottom-left, bottom-right, top-right, top-left, core/target.h):
//
//   e_vdk    = detected - projected                              (px, pixel-centre convention)
//   b_vk     = mean_d e_vdk                   the view's bias: what averaging frames cannot remove
//   bias_k   = mean_v b_vk                    the systematic bias of the case
//   view_rms = RMS_v,k |b_vk - bias_k|        the bias that depends on the sub-pixel phase (net of
//                                             the noise left in b_vk: noise^2 / draws)
//   noise    = RMS_v,d,k |e_vdk - b_vk|       what averaging frames removes (on sum_v (D_v - 1)
//                                             degrees of freedom)
//   radial   = bias_k . r_k,  r_k = unit(projected_k - projected centre of the tag)
//                              (> 0: outward along the tag's diagonal, the tag looks larger)
//   tangent  = bias_k . (r_k rotated by +90 degrees)
//
// for the raw AprilTag 3 corners and for the refined ones, so that the detector and the refinement
// are told apart. The renderer is checked without the detector: the rendered black area of the tag
// (sum over a white-bounded window of (white - value) / (white - black), no noise) against the
// exact area of the projected black cells (shoelace of the projected cell quadrilaterals).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera.h"
#include "detect/photometric_fit.h"

namespace calibench {

struct CornerBiasCase {
  double tag_px = 32.0;   // Side of the black square in pixels, at the tag centre's depth.
  double tilt_deg = 0.0;  // Viewing angle: rotation of the board about its x axis.
  double roll_deg = 0.0;  // In-plane rotation of the tag before the tilt.
  double blur_sigma_px = 0.5;
  Eigen::Vector2d centre_px{319.5, 239.5};
};

struct CornerBiasOptions {
  CameraIntrinsics camera{800.0, 800.0, 90.0, 319.5, 239.5};  // 640 x 480, no distortion.
  int width = 640, height = 480;
  int views = 8;                  // Sub-pixel shifted views of each case.
  int draws = 8;                  // Noise draws of each view.
  double noise_sigma_gray = 2.0;  // As the default sweeps.
  int supersample = 4;
  double quad_decimate = 2.0;  // As the default sweeps.
  uint64_t seed = 1;           // View v of case c and its draws derive from (seed, c, v).
  // The photometric fit is drawn through `camera` (lens-aware, photometric_fit.h) when it is
  // distorted; false: through a homography in pixels, as without a calibration.
  bool lens_aware_fit = false;
  bool Check(std::string* why) const;
};

struct CornerStats {
  Eigen::Vector2d bias = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  double radial_px = std::numeric_limits<double>::quiet_NaN();
  double tangent_px = std::numeric_limits<double>::quiet_NaN();
  double view_rms_px = std::numeric_limits<double>::quiet_NaN();
  double noise_rms_px = std::numeric_limits<double>::quiet_NaN();
};

struct CornerBiasResult {
  bool ok = false;
  std::string message;
  int detected_draws = 0;  // Of views x draws: the tag found and refined.
  std::array<CornerStats, 4> raw, refined;
  // The photometric tag fit (photometric_fit.h) from the same raw corners: its statistics, the
  // draws it fitted, why the others were refused, and its mean Cramer-Rao std per corner.
  std::array<CornerStats, 4> photometric;
  int photometric_draws = 0;
  std::array<int, kNumFitFailures> photometric_failures{};
  double photometric_crlb_px = std::numeric_limits<double>::quiet_NaN();
  double photometric_blur_px = std::numeric_limits<double>::quiet_NaN();  // Mean fitted sigma.
  // Mean time per tag (microseconds): AprilTag 3 on the whole frame, the edge fit, the
  // photometric fit.
  double detect_us = 0, refine_us = 0, photometric_us = 0;
  double photometric_iterations = 0;     // Mean LM iterations of the fits.
  double black_area_px2 = 0.0;           // Exact, of the projected black cells (view 0).
  double rendered_black_area_px2 = 0.0;  // Measured on view 0's noise-free rendering.
  double view_angle_deg = 0.0;           // Angle between the board normal and the line of sight.
};

// Measures one case; never throws (a failed result with its message).
CornerBiasResult MeasureCornerBias(const CornerBiasCase& c, int case_index,
                                   const CornerBiasOptions& options);

// The default study: viewing angle 0..70 deg, tag size 12..96 px, blur 0..1.5 px, and image
// position (centre, off-centre), each varied about the default sweeps' view (32 px, 0.5 px blur).
std::vector<CornerBiasCase> DefaultCornerBiasCases();

}  // namespace calibench
