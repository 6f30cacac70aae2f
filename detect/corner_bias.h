// The corner error of the rendered pipeline (sim/render.h -> AprilTag 3 -> corner refinement)
// against the exact projections, split into its bias and its noise (`calibench corner-bias`).
//
// One case is one view of a single tag36h11 tag (a 1 x 1 AprilGrid on its white board, with a 1-
// or 2-bit black border, and with or without Kalibr's corner squares) through one of the study's
// cameras (CornerBiasCamera: no lens, an EuRoC-like radtan lens, an equidistant fisheye, a 190 deg
// double-sphere lens with the tag past 90 deg). The tag's centre projects to `centre_px`, its
// black square would show a side of `tag_px` pixels there fronto-parallel (through the lens;
// `tag_edge_px` is the side as tilted), and the board is tilted by `tilt_deg` about the board's x
// axis after an in-plane rotation `roll_deg`. The case is seen in
// `views` views, each shifted by a random sub-pixel offset (uniform in [-0.5, 0.5] px) and rendered
// `draws` times with independent gray noise. Each stage (CornerStage) finds and refines the tag on
// the same frames (cropped to the tag's surroundings); per view v, draw d and corner k (detector
// order: bottom-left, bottom-right, top-right, top-left, sim/target.h):
//
//   e_vdk    = detected - projected                              (px, pixel-centre convention)
//   b_vk     = mean_d e_vdk                   the view's bias: what averaging frames cannot remove
//   bias_k   = mean_v b_vk                    the systematic bias of the case
//   view_rms = RMS_v,k |b_vk - bias_k|        the bias that depends on the sub-pixel phase (net of
//                                             the noise left in b_vk: noise^2 / draws)
//   noise    = RMS_v,d,k |e_vdk - b_vk|       what averaging frames removes (on sum_v (D_v - 1)
//                                             degrees of freedom)
//   rms      = sqrt(mean_v,d,k |e_vdk|^2 / 2) the whole error, per axis (bias included)
//   radial   = bias_k . r_k,  r_k = unit(projected_k - projected centre of the tag)
//                              (> 0: outward along the tag's diagonal, the tag looks larger)
//   tangent  = bias_k . (r_k rotated by +90 degrees)
//
// The floor of a case, `crlb_px`, is the mean Cramer-Rao std per axis of the photometric fit's
// corners (photometric_fit.h), from the lens-aware fit when the case has a lens. The renderer is
// checked without the detector (cases without lens or squares): the rendered black area of the
// tag (sum over a white-bounded window of (white - value) / (white - black), no noise) against the
// exact area of the projected black cells (shoelace of the projected cell quadrilaterals).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "detect/photometric_fit.h"

namespace calibench {

// The study's cameras. kNone: 640 x 480, f 800 px, no distortion. kRadTanEuroc: 752 x 480,
// f 458 px, k1 = -0.28, k2 = 0.074 (EuRoC's cam0). kEquidistant: 752 x 480, f 300 px,
// Kannala-Brandt k1 = 0.01, k2 = -0.002 (a 140 deg fisheye, TUM VI-like). kDoubleSphere190:
// 1024 x 1024, double sphere xi = 0.6, alpha = 0.6, f 423 px (95 deg from the axis lands 480 px
// from the centre: a 190 deg lens), the tag at 95 deg, facing the camera.
enum class CornerBiasLens { kNone, kRadTanEuroc, kEquidistant, kDoubleSphere190 };
// "none", "radtan_euroc", "equidistant", "double_sphere_190".
const char* CornerBiasLensName(CornerBiasLens lens);
struct CornerBiasCamera {
  CameraIntrinsics intrinsics;
  int width = 640, height = 480;
  // Where a tag sits by default: the image centre without a lens; with one, off axis, where the
  // lens bends the tag's edges (EuRoC-like: 0.06 px of sag over a 32 px edge).
  Eigen::Vector2d default_centre_px;
  // How a view is posed (MeasureCornerBias). false: the board faces the optical axis and the tag
  // centre sits at `depth` along it (Z). true (a lens past 90 deg, where such a board is seen
  // edge-on): the view on the axis at distance `depth`, turned to the tag's line of sight (about
  // the perpendicular to both), so the board faces the camera centre; tilt and roll as on the axis.
  bool faces_line_of_sight = false;
  static CornerBiasCamera Of(CornerBiasLens lens);
};

struct CornerBiasCase {
  CornerBiasLens lens = CornerBiasLens::kNone;
  int black_border_bits = 1;    // 1: AprilTag 3's layout; 2: Kalibr's.
  bool corner_squares = false;  // Kalibr's corner squares (AprilGrid::corner_squares).
  // The black square's mean side in pixels as the image shows it fronto-parallel at centre_px
  // (through the lens); tilting shortens it (tag_edge_px).
  double tag_px = 32.0;
  double tilt_deg = 0.0;  // Viewing angle: rotation of the board about its x axis.
  double roll_deg = 0.0;  // In-plane rotation of the tag before the tilt.
  double blur_sigma_px = 0.5;
  // NaN: the camera's default_centre_px.
  Eigen::Vector2d centre_px = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
};

struct CornerBiasOptions {
  int views = 8;                  // Sub-pixel shifted views of each case.
  int draws = 8;                  // Noise draws of each view.
  double noise_sigma_gray = 2.0;  // As the default sweeps.
  int supersample = 4;
  double quad_decimate = 2.0;  // As the default sweeps.
  uint64_t seed = 1;           // View v of case c and its draws derive from (seed, c, v).
  bool Check(std::string* why) const;
};

// How the tag's corners are found, every stage on the same frames:
//   kRaw          AprilTag 3 alone on the image (a tag joined to corner squares is not found);
//   kEdgeFit      the frame detector (frame_detector.h) with the edge fit: straight edges (curved
//                 for the fisheye), followed on corner squares by the saddle of each X-junction;
//   kPhotometric  the frame detector with the photometric fit through a homography in pixels;
//   kLensAware    the photometric fit drawn through the case's camera (cases with a lens only).
enum class CornerStage { kRaw, kEdgeFit, kPhotometric, kLensAware };
constexpr int kNumCornerStages = 4;
// "raw", "edge_fit" ("saddle" on corner squares), "photometric", "lens_aware".
const char* CornerStageName(CornerStage stage, bool corner_squares);

struct CornerStats {
  Eigen::Vector2d bias = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  double radial_px = std::numeric_limits<double>::quiet_NaN();
  double tangent_px = std::numeric_limits<double>::quiet_NaN();
  double view_rms_px = std::numeric_limits<double>::quiet_NaN();
  double noise_rms_px = std::numeric_limits<double>::quiet_NaN();
};

struct CornerStageResult {
  bool run = false;    // kLensAware runs only for cases with a lens.
  int detections = 0;  // Draws whose tag was found with its four corners.
  int failed = 0;      // Draws whose tag was not (views x draws - detections).
  std::array<CornerStats, 4> corners;
  double rms_px = std::numeric_limits<double>::quiet_NaN();  // Per axis, over all errors.
  // Photometric stages: the mean Cramer-Rao std per axis of the corners, the mean fitted blur,
  // and the tags refused by reason (photometric_fit.h).
  double crlb_px = std::numeric_limits<double>::quiet_NaN();
  double blur_px = std::numeric_limits<double>::quiet_NaN();
  std::array<int, kNumFitFailures> refused{};
  // Mean time per tag (microseconds) of the stage's whole detection: AprilTag 3 alone for kRaw,
  // detection + matching + refinement for the others (their refinement: the difference).
  double us_per_tag = 0;
};

struct CornerBiasResult {
  bool ok = false;  // The case ran and at least one stage found the tag.
  std::string message;
  std::array<CornerStageResult, kNumCornerStages> stages;
  const CornerStageResult& stage(CornerStage s) const { return stages[static_cast<int>(s)]; }
  // The case's floor: crlb_px of kLensAware when it ran, of kPhotometric otherwise.
  double crlb_px = std::numeric_limits<double>::quiet_NaN();
  // Without lens and corner squares (NaN otherwise): the exact area of the projected black cells
  // (view 0) and the one measured on view 0's noise-free rendering.
  double black_area_px2 = std::numeric_limits<double>::quiet_NaN();
  double rendered_black_area_px2 = std::numeric_limits<double>::quiet_NaN();
  double view_angle_deg = 0.0;  // Angle between the board normal and the line of sight.
  double tag_edge_px = 0.0;     // Mean side of the projected black square (view 0).
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();  // The tag centre's pixel (view 0).
};

// Measures one case; never throws (a failed result with its message).
CornerBiasResult MeasureCornerBias(const CornerBiasCase& c, int case_index,
                                   const CornerBiasOptions& options);

// The default study. Without a lens, a 1-bit tag (AprilTag 3's) varied one axis at a time about
// the default sweeps' view (32 px, 0.5 px blur, fronto-parallel): viewing angle 0..70 deg at two
// rolls, tag edge 15..60 px, blur 0..1.5 px, image position. Then for each of (no lens, 2-bit),
// (no lens, Kalibr grid: 2-bit with corner squares) and, for each lens, (1-bit) and (Kalibr grid):
// tilt 0..60 deg, tag edge 15..60 px and blur 0..1.5 px about the same view (the 190 deg lens's
// cases last).
std::vector<CornerBiasCase> DefaultCornerBiasCases();

}  // namespace calibench
