// Projection uncertainty: how far, in pixels, the projection of an observed ray may move when the
// calibration is re-made from new noise. mrcal's definition (its "projection uncertainty"
// documentation), with the camera frame's own uncertainty accounted for by averaging over the
// frames, as mrcal's original method does (not its newer cross-reprojection variant, which needs
// the whole optimisation at hand; the averaged method needs only the 16 x 16 matrix below, so a
// camera file can carry it).
//
// A calibration estimates the intrinsics theta and, per view v, cam_from_board_v = (R_v, t_v).
// Take a pixel q and a distance d (infinity by default). Unproject: p = d * ray(q) in the camera
// frame. In each board frame that point is x_v = cam_from_board_v^-1 p. A re-made calibration
// (theta', R_v', t_v') sees it at the average of cam_from_board_v' x_v over the views, and projects
// it through theta'. To first order, with the left perturbation R_v' = Exp(phi_v) R_v,
// t_v' = t_v + dt_v:
//     p' - p = -[p]x phi_bar + eps,  phi_bar = mean_v phi_v,  eps = mean_v ([t_v]x phi_v + dt_v),
// so the projection q' = Project(theta', p') depends on the calibration only through
//     z = [theta (10, the raw order of camera/camera.h, phi in radians), phi_bar (3, rad), eps
//     (3)],
// eps in the target's unit (metres). Var(q) = G Cov(z) G^T, G = [dq/dtheta, -dq/dp [p]x, dq/dp];
// at infinity p = ray(q) (the projection is invariant to the point's scale) and the eps columns
// vanish. Cov(z) = L Cov(theta, poses) L^T, with Cov(theta, poses) = sigma^2 (J^T J)^-1 of the
// whole refinement (sigma: the known pixel noise or sigma_hat from the residuals) and L the linear
// map above; RefineCalibration computes it (RefineResult::projection) with the poses' Schur
// complement, without forming the whole inverse.
//
// A gauge fixed instead (one board held, or the camera) gives a larger figure (mrcal's
// documentation says why); a single shared pose (a scenario's constant extrinsic) is the case of
// one view. The figure is formal: on real images, where the corner noise is not independent, it is
// too small (docs/uncertainty.md gives the measured factor and what calibrate does about it).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/image_grid.h"
#include "camera/pose.h"
#include "camera/projection_covariance.h"
#include "camera/rig.h"

namespace calibench {

// Cov(z) of the header comment: camera/projection_covariance.h's ProjectionCovariance.

// The linear map L of the header comment, from the tangent of one view's pose (3 of the quaternion
// tangent of ceres::EigenQuaternionManifold, whose rotation vector is twice it, then 3 of
// translation) to that view's share of [phi_bar, eps] (num_views: the views averaged over).
Eigen::Matrix<double, 6, 6> PoseTangentToFrameShare(const Rigid3& cam_from_board, int num_views);

// Cov(z) of an estimate that carries camera/estimate.h's 11 x 11 covariance C over [fku, fkv,
// phi_rad, u0, v0, delta (3, rad), x_C (3)] of its camera with one pose (the case of one view).
// With the perturbation R_C' = Exp(delta) R_C (parent frame), x_C' = x_C + dx_C and
// cam_from_parent = (R_C^T, -R_C^T x_C), a camera point moves by p' - p = [p]x R_C^T delta -
// R_C^T dx_C, so in z's convention (p' - p = -[p]x phi_bar + eps) phi_bar = -R_C^T delta and
// eps = -R_C^T dx_C: Cov(z) = L C L^T, L (16 x 11) = [I_5 on the pinhole intrinsics; -R_C^T on
// delta; -R_C^T on dx_C] (the distortion rows stay 0: C has none). The sign convention of C
// (estimate minus truth or truth minus estimate) does not matter as long as it is the same for
// every entry. R_C^T is cam_from_parent.rotation. False (out unchanged) unless C is 11 x 11 and
// finite. sigma_px is left 0 (the method's own noise model is inside C); num_views = 1.
bool ProjectionCovarianceOfEstimate(const Eigen::MatrixXd& estimate_covariance,
                                    const Rigid3& cam_from_parent, ProjectionCovariance* out);

// The uncertainty of one pixel's projection.
struct PixelUncertainty {
  Eigen::Matrix2d covariance_px2 = Eigen::Matrix2d::Zero();
  double worst_std_px = 0.0;     // sqrt of the larger eigenvalue: the ellipse's semi-major axis.
  double smallest_std_px = 0.0;  // The semi-minor axis.
  double major_angle_rad = 0.0;  // Direction of the major axis from the image's x axis.
};

// The worst-direction std (sqrt of the larger eigenvalue) of a 2 x 2 pixel covariance.
double WorstStdPx(const Eigen::Matrix2d& covariance_px2);
// The spread of pixels (e.g. one pixel's projections through re-made calibrations): their sample
// covariance about their mean, sum (q - mean)(q - mean)^T / (n - 1). Zero for fewer than 2.
Eigen::Matrix2d SampleCovariancePx2(const std::vector<Eigen::Vector2d>& pixels);

// The uncertainty at `pixel` for a point at `distance_m` (target units; infinity: a ray) through
// `camera`. False with *why where the pixel does not unproject (outside the lens's field) or the
// ray does not project back.
bool ProjectionUncertaintyAt(const CameraIntrinsics& camera, const ProjectionCovariance& covariance,
                             const Eigen::Vector2d& pixel, double distance_m, PixelUncertainty* out,
                             std::string* why);

struct UncertaintyMapOptions {
  int cols = 40;  // Grid samples across the image (rows follow the aspect ratio).
  double distance_m = std::numeric_limits<double>::infinity();  // Target units; infinity: rays.
};
// The worst-direction std over a grid of the image (camera/image_grid.h); NaN where a pixel does
// not unproject.
struct UncertaintyMap {
  ImageGrid worst_std_px;
  double median_px = std::numeric_limits<double>::quiet_NaN();  // Over the finite samples.
  double max_px = std::numeric_limits<double>::quiet_NaN();
  double centre_px = std::numeric_limits<double>::quiet_NaN();  // At the image centre.
};
UncertaintyMap ProjectionUncertaintyMap(const CameraIntrinsics& camera,
                                        const ProjectionCovariance& covariance, int image_width,
                                        int image_height, const UncertaintyMapOptions& options);
// Fills median_px, max_px (over the finite samples) and centre_px (the sample nearest the image
// centre) from map->worst_std_px.
void SummariseUncertaintyMap(UncertaintyMap* map);

// A rig's relative pose in pixels: where camera c sees what camera 0 sees at a pixel. The
// covariance of what carries it, z = [camera 0's 10 raw intrinsics, camera c's, the rotation and
// translation perturbation (r, dt) of cam_c_from_cam_0: R' = Exp(r) R, t' = t + dt], sigma^2
// included (batch/rig_refine.h fills it from the rig's joint covariance, the frames eliminated).
// The point at `distance_m` along camera 0's ray through pixel0 (infinity: the ray, and the
// relative translation drops out) is x_c = R (d u(theta_0, q0)) + t in camera c; its pixel
// q_c = pi(theta_c, x_c) moves by G dz, G = [dq_c/dtheta_0 (through the ray, by central
// differences of UnprojectToRay), dq_c/dtheta_c, -dq_c/dx [R d u]x, dq_c/dx], and
// Cov(q_c) = G Cov(z) G^T.
struct TransferCovariance {
  static constexpr int kSize = 26;
  using Matrix = Eigen::Matrix<double, kSize, kSize>;
  Matrix covariance = Matrix::Zero();
  bool set = false;
  bool IsSet() const { return set; }
};
// q_c alone (no covariance): false where pixel0 does not unproject through camera 0 or the point
// does not project into camera c's lens.
bool TransferPixel(const CameraIntrinsics& camera0, const CameraIntrinsics& camera_c,
                   const Rigid3& cam_c_from_cam_0, const Eigen::Vector2d& pixel0, double distance_m,
                   Eigen::Vector2d* pixel_c);
// The uncertainty of q_c (and q_c itself in *pixel_c when not null). False with *why where pixel0
// does not unproject through camera 0 or the point does not project into camera c's lens.
bool TransferUncertaintyAt(const CameraIntrinsics& camera0, const CameraIntrinsics& camera_c,
                           const Rigid3& cam_c_from_cam_0, const TransferCovariance& covariance,
                           const Eigen::Vector2d& pixel0, double distance_m, PixelUncertainty* out,
                           Eigen::Vector2d* pixel_c, std::string* why);

// TransferUncertaintyAt over a grid of camera 0's image (`zero`), NaN where the point does not
// land inside camera c's image (`camera_c`; sizes from each RigCamera).
UncertaintyMap TransferUncertaintyMap(const RigCamera& zero, const RigCamera& camera_c,
                                      const Rigid3& cam_c_from_cam_0,
                                      const TransferCovariance& covariance,
                                      const UncertaintyMapOptions& options);

// The pixel where `estimate` projects what `reference` sees at `pixel`: the point at `distance_m`
// along reference's ray, taken into each view's board frame by `reference_cam_from_board`, brought
// back by `estimate_cam_from_board` and averaged (the camera frame the uncertainty is defined in),
// then projected by `estimate`. Its distance from `pixel` is the estimate's projection error
// against the reference (the truth in a simulation, the full fit in a jackknife). False where
// either camera fails to (un)project or the pose lists differ in length or are empty.
bool ReprojectThroughEstimate(const CameraIntrinsics& reference, const CameraIntrinsics& estimate,
                              const std::vector<Rigid3>& reference_cam_from_board,
                              const std::vector<Rigid3>& estimate_cam_from_board,
                              const Eigen::Vector2d& pixel, double distance_m,
                              Eigen::Vector2d* reprojected);

}  // namespace calibench
