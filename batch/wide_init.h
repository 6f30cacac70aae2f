// A start for wide-angle and fisheye lenses (120-200+ degrees) from planar targets that needs
// neither cv::fisheye nor a pinhole Zhang, for partial boards and boards near the image circle's
// edge: the start of `calibrate` for the unified, eucm and double-sphere families, and for
// pinhole-equi when cv::fisheye::calibrate fails.
//
// 1. Profile scan. Mei's unified model without distortion gives the image radius of a ray at
//    theta from the axis as
//        r(theta) = f (1 + xi) sin(theta) / (cos(theta) + xi)      [px; f: the focal length on
//                                                                    the axis, gamma = f (1 + xi)]
//    and spans the radial profiles of real lenses with its one shape parameter: xi = 1 is the
//    stereographic 2 f tan(theta/2), xi = 1.75 follows the equidistant f theta to 90 deg within
//    2 %, xi = 2.4 the equisolid 2 f sin(theta/2) within 2 % (xi > 1: the field stops at
//    acos(-1/xi), 125 deg from the axis for 1.75). With the principal point at the image centre,
//    for each shape of `shape_xis` and each f of a log-spaced grid, every view's pixels are lifted
//    to rays (Mei's closed-form lift), its pose comes from its rays (BoardPoseFromRays: PnP after
//    turning the board's mean ray onto the axis, so boards past 90 degrees are posed too), and
//    the candidate scores (views posed, reprojection RMS in pixels), lexicographically. The best
//    f is refined by golden section in log f between its grid neighbours.
// 2. Polish: ceres on that unified camera with fku, fkv, the centre and xi free (no distortion),
//    from the scan's poses.
// 3. The requested family. Exact where the family holds the polished profile: unified itself;
//    eucm with alpha = xi / (1 + xi), beta = 1, f_eucm = gamma / (1 + xi) (eucm with beta = 1 is
//    unified). Otherwise a least-squares fit of the projection of a cone of rays at the observed
//    angles (up to 89.5 deg for equidistant), theta_j uniform:
//      equidistant: m(theta) = c theta (1 + k1 theta^2 + .. + k4 theta^8), linear in c, c k1, ..,
//        c k4, with fku_equi = c fku. It projects only in front (Z > 0): views with a ray at or
//        past 89.5 deg are left out, said in the message.
//      double sphere: xi_ds = +-0.2 (the better fit), then sin(theta) / m(theta) = (k + alpha
//        (d2 - k)) / s, k = xi_ds + cos(theta), d2 = |(sin(theta), k)|, linear in 1/s and
//        alpha/s, fku_ds = s fku. The double sphere with xi_ds = 0 (and alpha = xi / (1 + xi)) is
//        the profile exactly, but the parametrisation is singular there:
//        d log m/d xi_ds = (1 - 2 alpha) d log m/d alpha - d log f, so the Jacobian loses a rank
//        and ceres does not move off it (seen: 1 iteration, covariance rank deficient).
// 4. Each view's pose through that camera (BoardPoseFromRays): the start of RefineCalibration.
//
// It fails (IsUsable() false) when no candidate poses two views or when the start's RMS exceeds
// max_start_rms_px; the message then gives the best RMS found, with its shape and focal length.
//
// Example:
//   WideInitOptions o;
//   o.model = LensModel::kDoubleSphere;
//   o.image_width = 1024, o.image_height = 1024;
//   const WideInitResult start = InitializeWideCamera(views, o);
//   if (start.IsUsable()) RefineCalibration(used views, start.intrinsics, start.cam_from_board, r);
#pragma once

#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/pose.h"
#include "camera/view.h"
#include "util/status.h"

namespace calibench {

struct WideInitOptions {
  // The family to start: pinhole-equi, unified, eucm or double-sphere (radtan starts from zhang).
  LensModel model = LensModel::kDoubleSphere;
  int image_width = 0, image_height = 0;  // The principal point's guess is the image centre.
  std::vector<double> shape_xis = {1.0, 1.75, 2.4};  // Unified shapes scanned (header comment).
  // The focal lengths scanned, relative to the image's half short side R: a 200-degree lens whose
  // image circle fills the short side has f ~ 0.57 R (equidistant), a 90-degree lens across the
  // diagonal of a 4:3 sensor ~ 1.67 R.
  double min_focal_per_half_side = 0.15, max_focal_per_half_side = 5.0;
  int focal_steps = 48;     // Log-spaced (7.6 % apart with the defaults).
  int max_scan_views = 20;  // Views scored per candidate (evenly spaced); all are posed after.
  double max_start_rms_px =
      10.0;  // A start worse than this fails (the refinement would not fix it).
  bool Check(std::string* why) const;
};

struct WideInitResult : MethodSummary {
  CameraIntrinsics intrinsics;         // The requested family's start.
  std::vector<Rigid3> cam_from_board;  // One per used view.
  std::vector<int> used_views;         // Indices into the input.
  double rms_reproj_px = 0.0;          // The start's, over the used views.
  // The unified profile: the scan's best (shape xi, f, RMS over the scanned views) and the
  // polished camera with its RMS.
  double scan_xi = 0.0, scan_focal_px = 0.0, scan_rms_px = 0.0;
  int scan_views_posed = 0, scan_views = 0;
  CameraIntrinsics profile;
  double profile_rms_px = 0.0;
};

WideInitResult InitializeWideCamera(const std::vector<View>& planar_views,
                                    const WideInitOptions& options);

// The wide start serves these families (equidistant, unified, eucm, double-sphere).
bool WideInitServes(LensFamily family);

}  // namespace calibench
