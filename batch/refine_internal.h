// RefineCalibration's internals shared by its source files (batch/refine.h): the parameter
// storage of one problem, and the covariance computations of its header comment
// (refine_covariance.cc). Internal to batch/.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "batch/projection_uncertainty.h"
#include "batch/refine.h"
#include "camera/rig.h"

namespace calibench {
namespace refine_internal {

// The Ceres loss of `loss` at `scale_px` (nullptr: squared error), owned by the problem.
ceres::LossFunction* MakeLoss(RobustLoss loss, double scale_px);

// What is wrong with the solver options RefineOptions and RigRefineOptions share ("" when
// nothing): the loss, its scale, the iteration limit, the known pixel sigma.
std::string SolverOptionsProblem(RobustLoss loss, double loss_scale_px, int max_iterations,
                                 double known_pixel_sigma_px);

// Parameter storage for one problem: intrinsics and poses (quaternion x, y, z, w; translation).
struct Parameters {
  IntrinsicsArray intrinsics{};
  std::vector<std::array<double, 4>> rotations;
  std::vector<std::array<double, 3>> translations;

  Parameters(const CameraIntrinsics& k, const std::vector<Rigid3>& poses) {
    intrinsics = k.Params();
    for (const Rigid3& pose : poses) {
      const Eigen::Quaterniond q(pose.rotation);
      rotations.push_back({q.x(), q.y(), q.z(), q.w()});
      translations.push_back({pose.translation.x(), pose.translation.y(), pose.translation.z()});
    }
  }
  Rigid3 Pose(size_t i) const {
    const Eigen::Quaterniond q(rotations[i][3], rotations[i][0], rotations[i][1], rotations[i][2]);
    return {q.normalized().toRotationMatrix(),
            Eigen::Vector3d(translations[i][0], translations[i][1], translations[i][2])};
  }
};

// scale (J^T J)^-1 of the intrinsics block by ceres::Covariance (DENSE_SVD of the whole Jacobian):
// the reference, and IntrinsicsCovarianceAt's.
bool CovarianceOfIntrinsics(ceres::Problem* problem, Parameters* params, double scale,
                            IntrinsicsCovariance* covariance, std::string* why);
// The joint covariance (RefineResult::joint_covariance) of the intrinsics and the one shared pose.
bool JointCovariance(ceres::Problem* problem, Parameters* params, const std::vector<int>& fixed,
                     double scale, Eigen::MatrixXd* covariance, std::string* why);
// The intrinsics' covariance with one pose per view (the Schur complement of the poses), and with
// `projection` (may be null) Cov(z) of batch/projection_uncertainty.h.
bool PerViewIntrinsicsCovariance(ceres::Problem* problem, Parameters* params,
                                 const std::vector<int>& fixed, double scale,
                                 IntrinsicsCovariance* covariance, ProjectionCovariance* projection,
                                 std::string* why);

// The omnidirectional families' ranges as Ceres bounds on an intrinsics block (refine.cc's header
// comment): what RefineCalibration sets, for the rig refinement (batch/rig_refine.cc).
void SetIntrinsicsBounds(LensFamily family, double* intrinsics, ceres::Problem* problem);
// The inverse of a symmetric information matrix, or false with *why when its condition number, on
// the matrix scaled to a unit diagonal, passes 1e14 (refine_covariance.cc).
bool InvertInformationMatrix(const Eigen::MatrixXd& information, Eigen::MatrixXd* inverse,
                             std::string* why);

// The rig refinement's covariance (batch/rig_refine.cc FillRigCovariance) by camera: one frame's
// blocks of J^T J, B_f (rig parameters x frame pose) and D_f^-1, with the frame's pose; and where
// camera c's parameters sit among the rig's (its free raw intrinsics from intrinsics_at, its
// [d, t] in the rig at pose_at, -1 for none).
struct RigFrameBlocks {
  int frame;
  Rigid3 rig_from_board;
  Eigen::MatrixXd b;
  Eigen::Matrix<double, 6, 6> d_inverse;
};
struct RigCameraColumns {
  std::vector<int> free;
  int intrinsics_at = 0;
  int pose_at = -1;
};
// Camera c's Cov(z) (batch/projection_uncertainty.h), averaged over the frames it saw, from the
// Schur complement's inverse `s_inverse` (unscaled) and the frames' blocks (rig_projection.cc).
ProjectionCovariance RigCameraProjection(const std::vector<RigFrame>& frames, int c,
                                         const Rigid3& cam_from_rig,
                                         const RigCameraColumns& columns,
                                         const std::vector<RigFrameBlocks>& frame_blocks,
                                         const Eigen::MatrixXd& s_inverse, double sigma_px);

// The TransferCovariance (batch/projection_uncertainty.h) of camera c from the rig parameters'
// covariance `covariance` (sigma^2 included, the frames eliminated): cam_from_rig and columns of
// camera 0 and camera c, in that order. With R = R_c R_0^T and the perturbations R' = Exp(d) R,
// t' = t + dt of each cam_from_rig, cam_c_from_cam_0 moves by
//     r = d_c - R d_0,  dt = dt_c - R dt_0 + [R t_0]x r.
TransferCovariance RigTransferCovariance(const std::array<Rigid3, 2>& cam_from_rig,
                                         const std::array<RigCameraColumns, 2>& columns,
                                         const Eigen::MatrixXd& covariance);

}  // namespace refine_internal
}  // namespace calibench
