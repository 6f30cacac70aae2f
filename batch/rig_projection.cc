// Each rig camera's projection covariance from the rig's joint solve (refine_internal.h,
// RigCameraProjection; batch/rig_refine.cc FillRigCovariance gathers its blocks), and the
// covariance of what carries camera 0's rays into camera c (RigTransferCovariance).
#include "batch/refine_internal.h"

namespace calibench {
namespace refine_internal {

// Camera c's Cov(z) (batch/projection_uncertainty.h), averaged over the frames it saw. A point p
// in camera c, y = cam_from_rig_c^-1 p in the rig, moves with camera c's pose [d_c, dt_c] and the
// frames' [d_f, dt_f] (R' = Exp(d) R) by
//     -[p]x Phi + E,  Phi = d_c + R_c mean_f d_f,
//     E = [t_c]x Phi + dt_c + R_c mean_f ([t_f]x d_f + dt_f),
// so z_c = [theta_c, Phi, E] = K a + sum_f M_f b_f over the rig parameters a and the frame poses
// b_f. With the frames eliminated (S the Schur complement, W = sum_f M_f D_f^-1 B_f^T):
//     Cov(z_c) = sigma^2 ((K - W) S^-1 (K - W)^T + sum_f M_f D_f^-1 M_f^T).
ProjectionCovariance RigCameraProjection(const std::vector<RigFrame>& frames, int c,
                                         const Rigid3& cam_from_rig,
                                         const RigCameraColumns& columns,
                                         const std::vector<RigFrameBlocks>& frame_blocks,
                                         const Eigen::MatrixXd& s_inverse, double sigma_px) {
  constexpr int kZ = ProjectionCovariance::kSize;
  ProjectionCovariance out;
  const Eigen::Matrix3d& r_c = cam_from_rig.rotation;
  const Eigen::Matrix3d t_c = Hat(cam_from_rig.translation);
  std::vector<const RigFrameBlocks*> seen;
  for (const RigFrameBlocks& blocks : frame_blocks) {
    if (!frames[blocks.frame].views_by_camera[c].points.empty()) seen.push_back(&blocks);
  }
  if (seen.empty()) return out;
  const int size = static_cast<int>(s_inverse.rows());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(kZ, size);
  for (size_t i = 0; i < columns.free.size(); ++i) {
    k(columns.free[i], columns.intrinsics_at + static_cast<int>(i)) = 1.0;
  }
  if (columns.pose_at >= 0) {
    k.block<3, 3>(10, columns.pose_at).setIdentity();
    k.block<3, 3>(13, columns.pose_at) = t_c;
    k.block<3, 3>(13, columns.pose_at + 3).setIdentity();
  }
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(kZ, size);
  ProjectionCovariance::Matrix frame_part = ProjectionCovariance::Matrix::Zero();
  const double n = static_cast<double>(seen.size());
  for (const RigFrameBlocks* blocks : seen) {
    const Rigid3& rig_from_board = blocks->rig_from_board;
    Eigen::Matrix<double, kZ, 6> m = Eigen::Matrix<double, kZ, 6>::Zero();
    m.block<3, 3>(10, 0) = r_c / n;
    m.block<3, 3>(13, 0) = (t_c * r_c + r_c * Hat(rig_from_board.translation)) / n;
    m.block<3, 3>(13, 3) = r_c / n;
    w.noalias() += m * blocks->d_inverse * blocks->b.transpose();
    frame_part.noalias() += m * blocks->d_inverse * m.transpose();
  }
  const Eigen::MatrixXd k_w = k - w;
  out.covariance = sigma_px * sigma_px * (k_w * s_inverse * k_w.transpose() + frame_part);
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  out.sigma_px = sigma_px;
  out.num_views = static_cast<int>(seen.size());
  return out;
}

TransferCovariance RigTransferCovariance(const std::array<Rigid3, 2>& cam_from_rig,
                                         const std::array<RigCameraColumns, 2>& columns,
                                         const Eigen::MatrixXd& covariance) {
  constexpr int kZ = TransferCovariance::kSize;
  const Eigen::Matrix3d r = cam_from_rig[1].rotation * cam_from_rig[0].rotation.transpose();
  const Eigen::Matrix3d rt0 = Hat(r * cam_from_rig[0].translation);
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(kZ, covariance.rows());
  for (int k = 0; k < 2; ++k) {
    const RigCameraColumns& col = columns[k];
    for (size_t i = 0; i < col.free.size(); ++i) {
      l(10 * k + col.free[i], col.intrinsics_at + static_cast<int>(i)) = 1.0;
    }
    if (col.pose_at < 0) continue;  // Camera 0 defines the rig: its pose is fixed.
    // Camera 0's pose enters with -R, camera c's with I: r = d_c - R d_0.
    const Eigen::Matrix3d sign_r = k == 0 ? Eigen::Matrix3d(-r) : Eigen::Matrix3d::Identity();
    l.block<3, 3>(20, col.pose_at) = sign_r;
    l.block<3, 3>(23, col.pose_at) = rt0 * sign_r;
    l.block<3, 3>(23, col.pose_at + 3) = sign_r;
  }
  TransferCovariance out;
  out.covariance = l * covariance * l.transpose();
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  out.set = out.covariance.allFinite();
  return out;
}

}  // namespace refine_internal
}  // namespace calibench
