// RefineRig and RigCovarianceAt (batch/rig_refine.h); ComputeEpipolarErrors is rig_epipolar.cc's.
#include "batch/rig_refine.h"

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "batch/board_pose.h"
#include "batch/projection_jacobian.h"
#include "batch/refine_internal.h"
#include "batch/rig_reprojection_error.h"

namespace calibench {
namespace {

constexpr int kN = PinholeSkewCamera::kNumParams;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / M_PI;

using Quaternion = std::array<double, 4>;  // x, y, z, w (Eigen's storage order).
using Translation = std::array<double, 3>;

Quaternion ToQuaternion(const Eigen::Matrix3d& rotation) {
  const Eigen::Quaterniond q(rotation);
  return {q.x(), q.y(), q.z(), q.w()};
}
Rigid3 ToRigid(const Quaternion& q, const Translation& t) {
  return {Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix(),
          Eigen::Vector3d(t[0], t[1], t[2])};
}

// The parameter blocks of one rig problem (batch/rig_reprojection_error.h).
struct RigParameters {
  std::vector<IntrinsicsArray> intrinsics;
  std::vector<Quaternion> cam_q;
  std::vector<Translation> cam_t;
  std::vector<Quaternion> board_q;
  std::vector<Translation> board_t;

  RigParameters(const CameraRig& rig, const std::vector<Rigid3>& rig_from_board) {
    for (const RigCamera& camera : rig.cameras) {
      intrinsics.push_back(camera.intrinsics.Params());
      cam_q.push_back(ToQuaternion(camera.cam_from_rig.rotation));
      const Eigen::Vector3d& t = camera.cam_from_rig.translation;
      cam_t.push_back({t.x(), t.y(), t.z()});
    }
    for (const Rigid3& pose : rig_from_board) {
      board_q.push_back(ToQuaternion(pose.rotation));
      board_t.push_back({pose.translation.x(), pose.translation.y(), pose.translation.z()});
    }
  }
  Rigid3 CamFromRig(int c) const { return ToRigid(cam_q[c], cam_t[c]); }
  Rigid3 RigFromBoard(int f) const { return ToRigid(board_q[f], board_t[f]); }
};

// Camera c's intrinsics kept at their value: all with fix_intrinsics, else its model's.
std::vector<int> FixedOf(const RigRefineOptions& o, int c) {
  if (o.fix_intrinsics) {
    std::vector<int> all(kN);
    for (int i = 0; i < kN; ++i) all[i] = i;
    return all;
  }
  return FixedIntrinsics(o.models[c], o.estimate_skew);
}
std::vector<int> FreeOf(const RigRefineOptions& o, int c) {
  const std::vector<int> fixed = FixedOf(o, c);
  std::vector<int> free;
  for (int i = 0; i < kN; ++i) {
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) free.push_back(i);
  }
  return free;
}

std::string CameraName(const CameraRig& rig, int c) {
  return rig.cameras[c].name.empty() ? "camera " + std::to_string(c) : rig.cameras[c].name;
}

// What every entry point checks of its inputs; empty when they fit together.
std::string InputError(const std::vector<RigFrame>& frames, const CameraRig& rig,
                       const std::vector<Rigid3>& rig_from_board, const RigRefineOptions& options) {
  std::string why;
  if (!options.Check(&why)) return "rig options: " + why;
  const int num_cameras = rig.NumCameras();
  if (num_cameras < 2) return "a rig needs at least 2 cameras";
  if (static_cast<int>(options.models.size()) != num_cameras) {
    return "rig options: models must give one lens model per camera (" +
           std::to_string(options.models.size()) + " for " + std::to_string(num_cameras) + ")";
  }
  if (frames.empty() || rig_from_board.size() != frames.size()) {
    return "need frames and one rig_from_board per frame";
  }
  std::vector<int> seen(num_cameras, 0);
  for (size_t f = 0; f < frames.size(); ++f) {
    if (static_cast<int>(frames[f].views_by_camera.size()) != num_cameras) {
      return "frame " + std::to_string(f) + " does not hold one view per camera";
    }
    for (int c = 0; c < num_cameras; ++c) {
      const View& view = frames[f].views_by_camera[c];
      if (view.points.size() != view.pixels.size()) {
        return "frame " + std::to_string(f) + ", " + CameraName(rig, c) +
               ": points and pixels differ in number";
      }
      seen[c] += static_cast<int>(view.points.size());
    }
  }
  for (int c = 0; c < num_cameras; ++c) {
    if (!rig.cameras[c].intrinsics.Check(&why)) {
      return CameraName(rig, c) + ": initial intrinsics: " + why;
    }
    if (seen[c] == 0) return CameraName(rig, c) + " sees the target in no frame";
  }
  // Every camera must share frames with camera 0, directly or through others: a camera alone in
  // its frames has a pose the data cannot tell from its frames' poses.
  std::vector<bool> linked(num_cameras, false);
  linked[0] = true;
  for (bool grew = true; grew;) {
    grew = false;
    for (const RigFrame& frame : frames) {
      bool any_linked = false;
      for (int c = 0; c < num_cameras; ++c) {
        any_linked |= linked[c] && !frame.views_by_camera[c].points.empty();
      }
      if (!any_linked) continue;
      for (int c = 0; c < num_cameras; ++c) {
        if (!linked[c] && !frame.views_by_camera[c].points.empty()) linked[c] = grew = true;
      }
    }
  }
  std::string cut;
  for (int c = 0; c < num_cameras; ++c) {
    if (!linked[c]) cut += (cut.empty() ? "" : ", ") + CameraName(rig, c);
  }
  if (!cut.empty()) {
    return "no frame links " + cut + " to " + CameraName(rig, 0) +
           " (directly or through other cameras): cut off from the rig";
  }
  return "";
}

// The start of camera c in its model's family, as RefineCalibration's: an initial guess of another
// family contributes its pinhole part; the slots the model leaves out take their neutral values.
IntrinsicsArray StartIntrinsics(const CameraIntrinsics& initial, LensModel model,
                                const RigRefineOptions& options) {
  const LensFamily family = FamilyOf(model);
  CameraIntrinsics start = initial;
  if (start.family != family) {
    start = CameraIntrinsics();
    start.family = family;
    start.fku_px = initial.fku_px, start.fkv_px = initial.fkv_px, start.phi_deg = initial.phi_deg;
    start.u0_px = initial.u0_px, start.v0_px = initial.v0_px;
  }
  IntrinsicsArray params = start.Params();
  if (options.fix_intrinsics) return params;
  for (int i : FixedIntrinsics(model, options.estimate_skew)) {
    params[i] = i == 2 ? M_PI / 2 : std::string(ParamNames(family)[i]) == "beta" ? 1 : 0;
  }
  return params;
}

// Builds the problem of the header comment over *params; returns the number of points. Plain
// least squares: one residual block per view (camera c in frame f); a robust loss: one per point.
int BuildProblem(const std::vector<RigFrame>& frames, const RigRefineOptions& options,
                 RigParameters* params, ceres::Problem* problem) {
  int points = 0;
  const int num_cameras = static_cast<int>(params->intrinsics.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    for (int c = 0; c < num_cameras; ++c) {
      const View& view = frames[f].views_by_camera[c];
      if (view.points.empty()) continue;
      points += static_cast<int>(view.points.size());
      double* blocks[5] = {params->intrinsics[c].data(), params->cam_q[c].data(),
                           params->cam_t[c].data(), params->board_q[f].data(),
                           params->board_t[f].data()};
      const LensFamily family = FamilyOf(options.models[c]);
      if (options.loss == RobustLoss::kNone) {
        problem->AddResidualBlock(new RigViewCostFunction(view.points, view.pixels, family),
                                  nullptr, blocks, 5);
        continue;
      }
      for (size_t i = 0; i < view.points.size(); ++i) {
        problem->AddResidualBlock(
            new RigViewCostFunction({view.points[i]}, {view.pixels[i]}, family),
            refine_internal::MakeLoss(options.loss, options.loss_scale_px), blocks, 5);
      }
    }
  }
  for (int c = 0; c < num_cameras; ++c) {
    double* intrinsics = params->intrinsics[c].data();
    if (!problem->HasParameterBlock(intrinsics)) continue;
    if (options.fix_intrinsics) {
      problem->SetParameterBlockConstant(intrinsics);
    } else {
      const std::vector<int> fixed = FixedOf(options, c);
      if (!fixed.empty()) problem->SetManifold(intrinsics, new ceres::SubsetManifold(kN, fixed));
      refine_internal::SetIntrinsicsBounds(FamilyOf(options.models[c]), intrinsics, problem);
    }
    if (c == 0 || options.fix_extrinsics) {  // Camera 0 is the rig frame: the gauge.
      problem->SetParameterBlockConstant(params->cam_q[c].data());
      problem->SetParameterBlockConstant(params->cam_t[c].data());
    } else {
      problem->SetManifold(params->cam_q[c].data(), new ceres::EigenQuaternionManifold);
    }
  }
  for (Quaternion& q : params->board_q) {
    if (problem->HasParameterBlock(q.data())) {
      problem->SetManifold(q.data(), new ceres::EigenQuaternionManifold);
    }
  }
  return points;
}

// Camera c's pose uncertainty from its 6 x 6 covariance [d, t] (header comment).
RigPoseUncertainty PoseUncertaintyOf(const Eigen::Matrix<double, 6, 6>& covariance,
                                     const Rigid3& cam_from_rig) {
  RigPoseUncertainty out;
  out.covariance = covariance;
  // The camera's centre in the rig, c = -R^T t, moves with [d, t] as dc = -R^T ([t]x d + dt)
  // (R' = Exp(d) R: Exp(-d) t = t + [t]x d to first order).
  const Eigen::Matrix3d& r = cam_from_rig.rotation;
  const Eigen::Vector3d& t = cam_from_rig.translation;
  Eigen::Matrix3d t_cross;
  t_cross << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  Eigen::Matrix<double, 3, 6> d_centre;
  d_centre << -r.transpose() * t_cross, -r.transpose();
  const Eigen::Matrix3d cov_c = d_centre * covariance * d_centre.transpose();
  const Eigen::Vector3d centre = -r.transpose() * t;
  const double length = centre.norm();
  const Eigen::Vector3d u = centre / length;
  out.baseline_std_mm = 1000.0 * std::sqrt(std::max(0.0, u.dot(cov_c * u)));
  // The unit vector u = c / |c| moves by du = (I - u u^T) dc / |c|: the RMS angle |du| (rad) is
  // sqrt(trace(cov_u)), as the jackknife measures it (batch/jackknife.h).
  const Eigen::Matrix3d project = (Eigen::Matrix3d::Identity() - u * u.transpose()) / length;
  const Eigen::Matrix3d cov_u = project * cov_c * project.transpose();
  out.baseline_direction_std_deg = std::sqrt(std::max(0.0, cov_u.trace())) * kRadToDeg;
  // r = Log(Exp(d) R): its Jacobian in d at d = 0 by central differences (exact to ~1e-9 of its
  // entries; LogSO3 is smooth away from pi).
  constexpr double kStep = 1e-6;
  Eigen::Matrix3d d_r;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d step = kStep * Eigen::Vector3d::Unit(k);
    d_r.col(k) = (LogSO3(ExpSO3(step) * cam_from_rig.rotation) -
                  LogSO3(ExpSO3(-step) * cam_from_rig.rotation)) /
                 (2 * kStep);
  }
  const Eigen::Matrix3d cov_r = d_r * covariance.topLeftCorner<3, 3>() * d_r.transpose();
  out.rotation_std_deg = cov_r.diagonal().cwiseMax(0.0).cwiseSqrt() * kRadToDeg;
  return out;
}

// sigma^2 (J^T J)^-1 of the rig parameters (every camera's free intrinsics, then [d, t] of cameras
// 1..N-1 unless fix_extrinsics) with the frame poses marginalised: J in the tangents R' = Exp(d) R
// (rotations) and t' = t + dt, from the analytic projection Jacobians; each frame's 6 x 6 block D_f
// eliminated by the Schur complement S = A - sum_f B_f D_f^-1 B_f^T (a residual sees one frame
// pose). Dense: a rig has at most a few dozen such parameters. Fills intrinsics_std,
// intrinsics_covariance, pose_uncertainty and projection of *out (the loss is not applied: at a
// robust optimum the inliers' curvature).
bool FillRigCovariance(const std::vector<RigFrame>& frames, const RigParameters& params,
                       const RigRefineOptions& options, double sigma, RigRefineResult* out,
                       std::string* why) {
  const int num_cameras = static_cast<int>(params.intrinsics.size());
  std::vector<std::vector<int>> free(num_cameras);
  std::vector<int> intrinsics_at(num_cameras), pose_at(num_cameras, -1);
  int size = 0;
  for (int c = 0; c < num_cameras; ++c) {
    free[c] = FreeOf(options, c);
    intrinsics_at[c] = size;
    size += static_cast<int>(free[c].size());
  }
  if (!options.fix_extrinsics) {
    for (int c = 1; c < num_cameras; ++c) pose_at[c] = size, size += 6;
  }
  std::vector<Rigid3> cam_from_rig(num_cameras);
  std::vector<LensFamily> family(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    cam_from_rig[c] = params.CamFromRig(c);
    family[c] = FamilyOf(options.models[c]);
  }
  out->intrinsics_std.assign(num_cameras, IntrinsicsArray{});
  for (IntrinsicsArray& s : out->intrinsics_std) s.fill(kNaN);
  out->intrinsics_covariance.assign(num_cameras, IntrinsicsCovariance::Zero());
  out->pose_uncertainty.assign(num_cameras, RigPoseUncertainty());
  if (size == 0) return true;  // Nothing of the rig is estimated.
  Eigen::MatrixXd schur = Eigen::MatrixXd::Zero(size, size);
  Eigen::MatrixXd b(size, 6), j_rig(2, size);
  // Per frame seen: B_f and D_f^-1, for the cameras' projection covariance (RigProjection below).
  std::vector<refine_internal::RigFrameBlocks> frame_blocks;
  for (size_t f = 0; f < frames.size(); ++f) {
    const Rigid3 rig_from_board = params.RigFromBoard(static_cast<int>(f));
    Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
    b.setZero();
    bool seen = false;
    for (int c = 0; c < num_cameras; ++c) {
      const View& view = frames[f].views_by_camera[c];
      const Eigen::Matrix3d& r_c = cam_from_rig[c].rotation;
      for (const Eigen::Vector3d& x : view.points) {
        seen = true;
        const Eigen::Vector3d turned = rig_from_board.rotation * x;
        const Eigen::Vector3d point_in_rig = turned + rig_from_board.translation;
        const Eigen::Vector3d point_in_cam = cam_from_rig[c] * point_in_rig;
        ProjectionJacobian pj;
        if (!ProjectWithJacobian(family[c], params.intrinsics[c].data(), point_in_cam, true, &pj)) {
          if (why) *why = "covariance: a point does not project at the parameters";
          return false;
        }
        j_rig.setZero();
        for (size_t k = 0; k < free[c].size(); ++k) {
          j_rig.col(intrinsics_at[c] + static_cast<int>(k)) = pj.d_intrinsics.col(free[c][k]);
        }
        if (pose_at[c] >= 0) {
          j_rig.block<2, 3>(0, pose_at[c]) = -pj.d_point * Hat(r_c * point_in_rig);
          j_rig.block<2, 3>(0, pose_at[c] + 3) = pj.d_point;
        }
        Eigen::Matrix<double, 2, 6> j_frame;
        j_frame.leftCols<3>() = -pj.d_point * r_c * Hat(turned);
        j_frame.rightCols<3>() = pj.d_point * r_c;
        schur.noalias() += j_rig.transpose() * j_rig;
        b.noalias() += j_rig.transpose() * j_frame;
        d.noalias() += j_frame.transpose() * j_frame;
      }
    }
    if (!seen) continue;
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(d);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) {
      if (why) *why = "covariance: the pose of frame " + std::to_string(f) + " is not observable";
      return false;
    }
    schur.noalias() -= b * ldlt.solve(b.transpose());
    frame_blocks.push_back({static_cast<int>(f), rig_from_board, b,
                            ldlt.solve(Eigen::Matrix<double, 6, 6>::Identity())});
  }
  Eigen::MatrixXd inverse;
  if (!refine_internal::InvertInformationMatrix(schur, &inverse, why)) return false;
  const Eigen::MatrixXd covariance = sigma * sigma * inverse;
  out->projection.assign(num_cameras, ProjectionCovariance());
  out->transfer.assign(num_cameras, TransferCovariance());
  for (int c = 0; c < num_cameras; ++c) {
    out->projection[c] = refine_internal::RigCameraProjection(
        frames, c, cam_from_rig[c], {free[c], intrinsics_at[c], pose_at[c]}, frame_blocks, inverse,
        sigma);
    if (c > 0) {
      using refine_internal::RigCameraColumns;
      out->transfer[c] = refine_internal::RigTransferCovariance(
          {cam_from_rig[0], cam_from_rig[c]},
          {RigCameraColumns{free[0], intrinsics_at[0], pose_at[0]},
           RigCameraColumns{free[c], intrinsics_at[c], pose_at[c]}},
          covariance);
    }
  }
  for (int c = 0; c < num_cameras; ++c) {
    const int n = static_cast<int>(free[c].size());
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        out->intrinsics_covariance[c](free[c][i], free[c][j]) =
            covariance(intrinsics_at[c] + i, intrinsics_at[c] + j);
      }
      out->intrinsics_std[c][free[c][i]] =
          std::sqrt(covariance(intrinsics_at[c] + i, intrinsics_at[c] + i));
    }
    if (pose_at[c] >= 0) {
      out->pose_uncertainty[c] =
          PoseUncertaintyOf(covariance.block<6, 6>(pose_at[c], pose_at[c]), cam_from_rig[c]);
    }
  }
  return true;
}

// The solved rig, frame poses, RMS (overall, per camera, per frame) and sigma_hat; false when
// there are fewer residuals than free parameters.
bool FillSolution(const std::vector<RigFrame>& frames, const CameraRig& initial,
                  const RigParameters& params, const RigRefineOptions& options,
                  RigRefineResult* result) {
  const int num_cameras = initial.NumCameras();
  result->rig = initial;
  for (int c = 0; c < num_cameras; ++c) {
    // What was held is handed back as given (the quaternion round trip would move it by ~1e-16).
    RigCamera& camera = result->rig.cameras[c];
    const LensFamily family = FamilyOf(options.models[c]);
    if (!options.fix_intrinsics || camera.intrinsics.family != family) {
      camera.intrinsics = CameraIntrinsics::FromParams(params.intrinsics[c].data(), family);
    }
    camera.lens_model = options.models[c];
    if (c == 0) {
      camera.cam_from_rig = Rigid3();
    } else if (!options.fix_extrinsics) {
      camera.cam_from_rig = params.CamFromRig(c);
    }
  }
  result->rig_from_board.clear();
  for (size_t f = 0; f < frames.size(); ++f) {
    result->rig_from_board.push_back(params.RigFromBoard(static_cast<int>(f)));
  }
  std::vector<double> camera_sq(num_cameras, 0.0);
  std::vector<int> camera_points(num_cameras, 0);
  int seen_frames = 0;
  result->frame_rms_px.assign(frames.size(), std::vector<double>(num_cameras, kNaN));
  for (size_t f = 0; f < frames.size(); ++f) {
    bool seen = false;
    for (int c = 0; c < num_cameras; ++c) {
      const View& view = frames[f].views_by_camera[c];
      if (view.points.empty()) continue;
      seen = true;
      double sum_sq = 0;
      ViewSquaredErrorPx2(view, result->rig.cameras[c].intrinsics,
                          result->rig.cameras[c].cam_from_rig * result->rig_from_board[f], &sum_sq);
      camera_sq[c] += sum_sq;
      camera_points[c] += static_cast<int>(view.points.size());
      result->frame_rms_px[f][c] = std::sqrt(sum_sq / static_cast<double>(view.points.size()));
    }
    seen_frames += seen ? 1 : 0;
  }
  double sum_sq = 0;
  int free_params = (options.fix_extrinsics ? 0 : 6 * (num_cameras - 1)) + 6 * seen_frames;
  result->camera_rms_px.assign(num_cameras, kNaN);
  for (int c = 0; c < num_cameras; ++c) {
    sum_sq += camera_sq[c];
    free_params += static_cast<int>(FreeOf(options, c).size());
    if (camera_points[c] > 0) result->camera_rms_px[c] = std::sqrt(camera_sq[c] / camera_points[c]);
  }
  result->rms_reproj_px = std::sqrt(sum_sq / std::max(1, result->num_points));
  const int dof = 2 * result->num_points - free_params;
  if (dof <= 0) return false;
  result->sigma_hat_px = std::sqrt(sum_sq / dof);
  return true;
}

// Where a failed solve is traced to, from its start: the first view (frame, camera) with a point
// that does not project (behind the camera or outside the lens's region: Ceres cannot evaluate
// it), else the view farthest from the start (largest RMS). Empty without views.
std::string TraceFailure(const std::vector<RigFrame>& frames, const CameraRig& rig,
                         const RigParameters& start, const RigRefineOptions& options) {
  std::string worst;
  double worst_rms = -1;
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string frame =
        frames[f].name.empty() ? "frame " + std::to_string(f) : "frame " + frames[f].name;
    for (int c = 0; c < rig.NumCameras(); ++c) {
      const View& view = frames[f].views_by_camera[c];
      if (view.points.empty()) continue;
      const CameraIntrinsics k =
          CameraIntrinsics::FromParams(start.intrinsics[c].data(), FamilyOf(options.models[c]));
      double sum_sq = 0;
      const std::string where = frame + ", " + CameraName(rig, c);
      if (!ViewSquaredErrorPx2(
              view, k, start.CamFromRig(c) * start.RigFromBoard(static_cast<int>(f)), &sum_sq)) {
        return where +
               ": a point does not project at the start (behind the camera or outside the lens's "
               "region)";
      }
      const double rms = std::sqrt(sum_sq / static_cast<double>(view.points.size()));
      if (rms > worst_rms) {
        worst_rms = rms;
        char line[64];
        std::snprintf(line, sizeof(line), " (RMS %.3g px)", rms);
        worst = where + ": the view farthest from the start" + line;
      }
    }
  }
  return worst;
}

}  // namespace

bool RigRefineOptions::Check(std::string* why) const {
  std::string msg;
  if (models.empty()) {
    msg = "models must give one lens model per camera (none given)";
  } else {
    msg = refine_internal::SolverOptionsProblem(loss, loss_scale_px, max_iterations,
                                                known_pixel_sigma_px);
  }
  if (msg.empty()) return true;
  if (why != nullptr) *why = msg;
  return false;
}

RigRefineResult RefineRig(const std::vector<RigFrame>& frames, const CameraRig& initial,
                          const std::vector<Rigid3>& initial_rig_from_board,
                          const RigRefineOptions& options) {
  const SummaryClock clock;
  RigRefineResult result;
  const auto finish = [&](MethodStatus status, const std::string& message) {
    return clock.Finish(&result, status, message);
  };
  const std::string input_error = InputError(frames, initial, initial_rig_from_board, options);
  if (!input_error.empty()) return finish(MethodStatus::kFailed, input_error);
  RigParameters params(initial, initial_rig_from_board);
  for (int c = 0; c < initial.NumCameras(); ++c) {
    params.intrinsics[c] =
        StartIntrinsics(initial.cameras[c].intrinsics, options.models[c], options);
  }
  params.cam_q[0] = {0, 0, 0, 1};
  params.cam_t[0] = {0, 0, 0};
  const RigParameters start = params;
  ceres::Problem problem;
  result.num_points = BuildProblem(frames, options, &params, &problem);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  // As RefineCalibration's (batch/refine.cc): tight tolerances, LM started near Gauss-Newton.
  solver_options.function_tolerance = 1e-10;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-10;
  solver_options.num_threads = 1;
  solver_options.initial_trust_region_radius = 1e6;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  result.iterations = static_cast<long>(summary.iterations.size());
  if (!summary.IsSolutionUsable() || summary.termination_type == ceres::NO_CONVERGENCE) {
    const std::string traced = TraceFailure(frames, initial, start, options);
    return finish(MethodStatus::kFailed,
                  "ceres: " + summary.message + (traced.empty() ? "" : " Traced to " + traced));
  }
  if (!FillSolution(frames, initial, params, options, &result)) {
    return finish(MethodStatus::kFailed, "fewer residuals than free parameters");
  }
  if (options.compute_covariance) {
    const double sigma =
        options.known_pixel_sigma_px > 0 ? options.known_pixel_sigma_px : result.sigma_hat_px;
    std::string why;
    if (!FillRigCovariance(frames, params, options, sigma, &result, &why)) {
      return finish(MethodStatus::kFailed, why);
    }
  } else {
    result.intrinsics_std.assign(initial.NumCameras(), IntrinsicsArray{});
    for (IntrinsicsArray& s : result.intrinsics_std) s.fill(kNaN);
    result.intrinsics_covariance.assign(initial.NumCameras(), IntrinsicsCovariance::Zero());
    result.pose_uncertainty.assign(initial.NumCameras(), RigPoseUncertainty());
  }
  return finish(MethodStatus::kOk, "");
}

bool RigCovarianceAt(const std::vector<RigFrame>& frames, const CameraRig& rig,
                     const std::vector<Rigid3>& rig_from_board, const RigRefineOptions& options,
                     double pixel_sigma_px, RigRefineResult* bound, std::string* why) {
  const std::string input_error = InputError(frames, rig, rig_from_board, options);
  if (!input_error.empty()) {
    if (why) *why = input_error;
    return false;
  }
  for (int c = 0; c < rig.NumCameras(); ++c) {
    if (rig.cameras[c].intrinsics.family != FamilyOf(options.models[c])) {
      if (why) {
        *why = "no bound: " + CameraName(rig, c) + "'s lens family (" +
               ToString(rig.cameras[c].intrinsics.family) + ") is not its model's (" +
               ToString(options.models[c]) + ")";
      }
      return false;
    }
  }
  const RigParameters params(rig, rig_from_board);
  RigRefineResult out;
  out.rig = rig;
  out.rig_from_board = rig_from_board;
  for (const RigFrame& frame : frames) {
    for (const View& view : frame.views_by_camera) out.num_points += view.points.size();
  }
  if (!FillRigCovariance(frames, params, options, pixel_sigma_px, &out, why)) return false;
  out.status = MethodStatus::kOk;
  *bound = out;
  return true;
}

}  // namespace calibench
