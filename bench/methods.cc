#include "bench/methods.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <mutex>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "adaptive/estimator.h"
#include "adaptive/theta.h"
#include "batch/dlt.h"
#include "batch/refine.h"
#include "batch/zhang.h"

namespace calibench {
namespace {

// Zhang's intrinsics and the constant extrinsic it implies (for ceres' initialisation).
struct ZhangExtrinsics {
  bool usable = false;
  std::string message;
  CameraIntrinsics intrinsics;
  Rigid3 parent_from_cam;
};

// Per-point RMS reprojection error of M_hat over all frames of the source.
double RmsReprojection(const MeasurementSource& source, const Matrix34d& m_hat) {
  Frame frame;
  double sum = 0.0;
  long count = 0;
  for (int k = 0; k < source.NumFrames(); ++k) {
    source.GetFrame(k, &frame);
    for (size_t i = 0; i < frame.pixels.size(); ++i) {
      const Eigen::Vector3d m = m_hat * frame.points_in_parent[i].homogeneous();
      sum += (m.hnormalized() - frame.pixels[i]).squaredNorm();
      ++count;
    }
  }
  return count ? std::sqrt(sum / count) : kUnset;
}

void FillCameraErrors(const ScenarioConfig& s, const RecoveredCamera& cam, RunRow* row) {
  const CameraIntrinsics& k = cam.intrinsics;
  row->fku = k.fku_px;
  row->fkv = k.fkv_px;
  row->phi_deg = k.phi_deg;
  row->u0 = k.u0_px;
  row->v0 = k.v0_px;
  const Eigen::Matrix3d& r_c = cam.parent_from_cam.rotation;
  // For an (opted-in) improper matrix the angles are those of -R_C, a proper rotation.
  const Eigen::Vector3d rpy = RollPitchYawDeg(cam.improper ? Eigen::Matrix3d(-r_c) : r_c);
  row->rc_roll_deg = rpy[0];
  row->rc_pitch_deg = rpy[1];
  row->rc_yaw_deg = rpy[2];
  const Eigen::Vector3d& x_c = cam.parent_from_cam.translation;
  row->xc_x = x_c[0];
  row->xc_y = x_c[1];
  row->xc_z = x_c[2];
  const CameraIntrinsics& t = s.truth.intrinsics;
  row->err_fku = k.fku_px - t.fku_px;
  row->err_fkv = k.fkv_px - t.fkv_px;
  row->err_phi_deg = k.phi_deg - t.phi_deg;
  row->err_u0 = k.u0_px - t.u0_px;
  row->err_v0 = k.v0_px - t.v0_px;
  row->rot_err_deg = RotationAngleDeg(r_c, s.truth.r_c);
  row->err_xc_norm = (x_c - s.truth.x_c).norm();
  row->ortho_defect = cam.orthogonality_defect;
  row->improper = cam.improper ? 1 : 0;
}

Vector16d TrueTheta(const ScenarioConfig& s) {
  return ThetaFromCamera(s.truth.intrinsics, s.truth.ParentFromCam().Inverse());
}

// Every n-th of `samples`, at most `max_samples` of them, always keeping the last.
std::vector<std::pair<double, double>> Thin(const std::vector<std::pair<double, double>>& samples,
                                            int max_samples) {
  if (max_samples < 2 || static_cast<int>(samples.size()) <= max_samples) return samples;
  std::vector<std::pair<double, double>> kept;
  const double stride = static_cast<double>(samples.size() - 1) / (max_samples - 1);
  for (int i = 0; i < max_samples; ++i) {
    kept.push_back(samples[static_cast<size_t>(std::lround(i * stride))]);
  }
  return kept;
}

// Below this PersistentExcitationIndex the adaptive row says it is not identifiable. Measured on
// the thesis sims: the unexcited ones (n = 1, 2, 5 with small motion; no motion) have <= 1.1e-6,
// every excited one >= 5.2e-5; 1e-5 sits between the two groups.
constexpr double kMinIdentifiablePeIndex = 1e-5;

RunRow RunAdaptive(const ScenarioConfig& s, const MeasurementSource& source, RunRow row,
                   const MethodSelection& selection) {
  row.method = "adaptive";
  const Vector16d theta_true = TrueTheta(s);
  const CameraSpec& init = s.adaptive.initial;
  const Vector16d theta0 = ThetaFromCamera(init.intrinsics, init.ParentFromCam().Inverse());
  // Convergence time: the first recorded t after the last one with ||theta~|| >= tol.
  const double tol = s.adaptive.convergence_tol;
  double last_above = -1.0;
  double first_after = 0.0;
  bool pending = false;
  std::vector<std::pair<double, double>> curve;
  auto observer = [&](double t, const Vector16d& theta_hat) {
    const double error = ThetaError(theta_true, theta_hat);
    if (selection.record_curve) curve.emplace_back(t, error);
    if (error >= tol) {
      last_above = t;
      pending = true;
    } else if (pending) {
      first_after = t;
      pending = false;
    }
  };
  const AdaptiveSummary summary =
      RunAdaptiveEstimator(source, theta0, s.adaptive.options, observer);
  row.status = ToString(summary.status);
  row.message = summary.message;
  row.steps = summary.iterations;
  row.wall_ms = summary.wall_ms;
  row.theta_err_norm = ThetaError(theta_true, summary.theta_hat);
  row.curve = Thin(curve, selection.curve_samples);
  if (!summary.IsUsable()) return row;
  row.converge_time_s = pending ? kUnset : (last_above < 0 ? 0.0 : first_after);
  row.pe_min_eig = PersistentExcitationIndex(summary.information, summary.theta_hat);
  row.rms_reproj_px = RmsReprojection(source, MFromTheta(summary.theta_hat));

  Frame last;
  source.Measure(source.Duration(), static_cast<int>(source.Breakpoints().size()) - 2, &last);
  RecoveredCamera cam;
  std::string why;
  if (!RecoverCamera(summary.theta_hat, last.points_in_parent, &cam, &why)) {
    row.status = "failed";
    row.message = "parameter recovery: " + why;
    return row;
  }
  FillCameraErrors(s, cam, &row);
  if (cam.improper && !s.truth.allow_improper_rotation) {
    row.message = "recovered rotation is improper (det < 0)";
  }
  if (row.pe_min_eig < kMinIdentifiablePeIndex) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "not identifiable: persistent-excitation index %.2g < %.0e, so theta_hat is one "
                  "of many that fit (too few points or too little motion)",
                  row.pe_min_eig, kMinIdentifiablePeIndex);
    row.message += (row.message.empty() ? "" : "; ") + std::string(text);
  }
  return row;
}

// The source's frames as views of the parent frame (what the batch methods see), read once.
struct FrameViews {
  std::vector<View> views;
  std::vector<double> times_s;
  std::vector<std::vector<int>> point_ids;  // Per view: the scene point of each entry.
};
FrameViews ReadFrames(const MeasurementSource& source) {
  FrameViews frames;
  frames.views.resize(source.NumFrames());
  frames.times_s.resize(source.NumFrames());
  frames.point_ids.resize(source.NumFrames());
  Frame frame;
  for (int k = 0; k < source.NumFrames(); ++k) {
    source.GetFrame(k, &frame);
    for (size_t i = 0; i < frame.pixels.size(); ++i) {
      frames.point_ids[k].push_back(frame.PointId(i));
    }
    frames.views[k].points = std::move(frame.points_in_parent);
    frames.views[k].pixels = std::move(frame.pixels);
    frames.times_s[k] = frame.time_s;
  }
  return frames;
}

// The thesis error of a camera estimate; distortion is not part of theta (M = A [R | t]).
double ThetaErrorOf(const ScenarioConfig& s, CameraIntrinsics intrinsics,
                    const Rigid3& cam_from_parent) {
  intrinsics.k1 = intrinsics.k2 = intrinsics.p1 = intrinsics.p2 = intrinsics.k3 = 0;
  return ThetaError(TrueTheta(s), ThetaFromCamera(intrinsics, cam_from_parent));
}

RunRow RunDlt(const ScenarioConfig& s, const std::vector<View>& views, RunRow row,
              DltResult* result) {
  row.method = "dlt";
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  for (const View& v : views) {
    points.insert(points.end(), v.points.begin(), v.points.end());
    pixels.insert(pixels.end(), v.pixels.begin(), v.pixels.end());
  }
  *result = EstimateDlt(points, pixels, s.dlt.options);
  row.status = ToString(result->status);
  row.message = result->message;
  row.wall_ms = result->wall_ms;
  row.steps = result->iterations;
  if (!result->IsUsable()) return row;
  row.theta_err_norm = ThetaError(TrueTheta(s), ThetaFromM(result->m));
  row.rms_reproj_px = result->rms_reproj_px;
  FillCameraErrors(s, result->camera, &row);
  return row;
}

// Cramer-Rao bound of the scenario's intrinsics for its pixel noise (NaN without pixel noise, or
// with noise on the 3D points, which the bound does not model). It depends on the scenario alone
// (exact points, the truth, sigma; J does not involve the noisy pixels), so the trials of a
// scenario share one computation through `shared` when given.
void FillCrlb(const ScenarioConfig& s, const std::vector<View>& views, ScenarioShared* shared,
              RunRow* row) {
  const NoiseOptions& noise = s.measurements.noise;
  if (!(noise.pixel_sigma_px > 0) || noise.point_sigma_m > 0) return;
  auto compute = [&](ScenarioShared* out) {
    IntrinsicsCovariance cov;
    out->crlb_valid =
        IntrinsicsCovarianceAt(views, s.truth.intrinsics, {s.truth.ParentFromCam().Inverse()},
                               s.ceres.options, noise.pixel_sigma_px, &cov, nullptr);
    const double deg = 180.0 / M_PI;
    out->crlb_std = {std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1)),
                     s.ceres.options.estimate_skew ? std::sqrt(cov(2, 2)) * deg : kUnset,
                     std::sqrt(cov(3, 3)), std::sqrt(cov(4, 4))};
  };
  ScenarioShared local;
  if (shared != nullptr) {
    std::call_once(shared->crlb_once, compute, shared);
  } else {
    compute(&local);
    shared = &local;
  }
  if (!shared->crlb_valid) return;
  row->crlb_fku = shared->crlb_std[0];
  row->crlb_fkv = shared->crlb_std[1];
  row->crlb_phi_deg = shared->crlb_std[2];
  row->crlb_u0 = shared->crlb_std[3];
  row->crlb_v0 = shared->crlb_std[4];
}

RunRow RunCeres(const ScenarioConfig& s, const std::vector<View>& views, const DltResult& dlt,
                const ZhangExtrinsics& zhang, ScenarioShared* shared, RunRow row) {
  row.method = "ceres";
  const bool from_zhang = s.ceres.init == "zhang";
  if (from_zhang ? !zhang.usable : !dlt.IsUsable()) {
    row.status = "failed";
    row.message = "initialisation (" + s.ceres.init +
                  ") failed: " + (from_zhang ? zhang.message : dlt.message);
    return row;
  }
  const CameraIntrinsics init = from_zhang ? zhang.intrinsics : dlt.camera.intrinsics;
  const Rigid3 parent_from_cam = from_zhang ? zhang.parent_from_cam : dlt.camera.parent_from_cam;
  const RefineResult r =
      RefineCalibration(views, init, {parent_from_cam.Inverse()}, s.ceres.options);
  row.status = ToString(r.status);
  row.message = r.message;
  row.wall_ms = r.wall_ms;
  row.steps = r.iterations;
  FillCrlb(s, views, shared, &row);
  if (!r.IsUsable()) return row;
  DecomposedCamera cam;
  cam.intrinsics = r.intrinsics;
  cam.parent_from_cam = r.cam_from_object[0].Inverse();
  FillCameraErrors(s, cam, &row);
  row.theta_err_norm = ThetaErrorOf(s, r.intrinsics, r.cam_from_object[0]);
  row.rms_reproj_px = r.rms_reproj_px;
  const double deg = 180.0 / M_PI;
  row.std_fku = r.intrinsics_std[0];
  row.std_fkv = r.intrinsics_std[1];
  row.std_phi_deg = r.intrinsics_std[2] * deg;
  row.std_u0 = r.intrinsics_std[3];
  row.std_v0 = r.intrinsics_std[4];
  return row;
}

// Chordal L2 mean of rotations (the SO(3) projection of their sum) and the mean position.
Rigid3 AveragePoses(const std::vector<Rigid3>& poses) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (const Rigid3& p : poses) {
    sum += p.rotation;
    position += p.translation;
  }
  return {ProjectToSO3(sum), position / static_cast<double>(poses.size())};
}

// Extrinsic by hand-eye calibration (Tsai) from the views of one board:
//   moving camera (eye-in-hand):  gripper = body, base = world, target = board fixed in W;
//       result cam2gripper = body_from_cam = parent_from_cam.
//   fixed camera (eye-to-hand):   pass base2gripper (body_from_world) as the gripper poses;
//       the result is cam2base = world_from_cam = parent_from_cam.
bool HandEye(const std::vector<Rigid3>& parent_from_points,
             const std::vector<Rigid3>& cam_from_board, Rigid3* parent_from_cam, std::string* why) {
  std::vector<cv::Mat> r_g2b, t_g2b, r_t2c, t_t2c;
  // Tsai's method needs relative rotations about at least two non-parallel axes.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  for (size_t i = 1; i < parent_from_points.size(); ++i) {
    const Eigen::AngleAxisd rel(parent_from_points[i].rotation *
                                parent_from_points[i - 1].rotation.transpose());
    if (rel.angle() > 1e-3) axes += rel.axis() * rel.axis().transpose();
  }
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(axes).eigenvalues();
  if (!(spread[1] > 1e-3 * spread[2])) {
    if (why) {
      *why =
          "hand-eye is degenerate: the body rotates about a single axis (or not at all); "
          "it needs rotations about two non-parallel axes";
    }
    return false;
  }
  for (size_t i = 0; i < cam_from_board.size(); ++i) {
    // Moving: parent_from_points = body_from_world, whose inverse is gripper2base (eye-in-hand).
    // Fixed: parent_from_points = world_from_body, whose inverse is base2gripper (eye-to-hand).
    const Rigid3 gripper = parent_from_points[i].Inverse();
    cv::Mat r, t, rc, tc;
    cv::eigen2cv(Eigen::Matrix3d(gripper.rotation), r);
    cv::eigen2cv(Eigen::Vector3d(gripper.translation), t);
    cv::eigen2cv(Eigen::Matrix3d(cam_from_board[i].rotation), rc);
    cv::eigen2cv(Eigen::Vector3d(cam_from_board[i].translation), tc);
    r_g2b.push_back(r);
    t_g2b.push_back(t);
    r_t2c.push_back(rc);
    t_t2c.push_back(tc);
  }
  if (r_g2b.size() < 3) {
    if (why) *why = "hand-eye needs at least 3 views of board 0";
    return false;
  }
  cv::Mat r_out, t_out;
  try {
    cv::calibrateHandEye(r_g2b, t_g2b, r_t2c, t_t2c, r_out, t_out, cv::CALIB_HAND_EYE_TSAI);
  } catch (const cv::Exception& e) {
    if (why) *why = std::string("cv::calibrateHandEye: ") + e.what();
    return false;
  }
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  cv::cv2eigen(r_out, r);
  cv::cv2eigen(t_out, t);
  *parent_from_cam = {ProjectToSO3(r), t};
  return parent_from_cam->rotation.allFinite() && t.allFinite();
}

std::vector<RunRow> RunZhang(const ScenarioConfig& s, const SceneTruth& scene,
                             const FrameViews& frames, const RunRow& base, ZhangExtrinsics* out) {
  RunRow row = base;
  row.method = "zhang";
  RunRow hand_eye_row = base;
  hand_eye_row.method = "zhang_handeye";
  auto fail = [&](const std::string& message) {
    out->message = message;
    for (RunRow* r : {&row, &hand_eye_row}) {
      r->status = "failed";
      r->message = message;
    }
    return std::vector<RunRow>{row, hand_eye_row};
  };
  const std::vector<ScenarioConfig::BoardLayout> layouts = s.BoardLayouts();
  if (layouts.empty()) {
    return fail("zhang needs planar boards: points: {boards: [...]} or {aprilgrids: [...]}");
  }
  // (frame, board) views, every view_stride-th frame, thinned further to max_views; a board seen
  // with fewer than kMinViewPoints points in a frame (partly detected) gives no view.
  constexpr size_t kMinViewPoints = 8;
  int stride = s.zhang.view_stride;
  const int num_frames = static_cast<int>(frames.views.size());
  const int boards = static_cast<int>(layouts.size());
  if (s.zhang.max_views > 0) {
    stride = std::max(stride, (num_frames * boards + s.zhang.max_views - 1) / s.zhang.max_views);
  }
  std::vector<View> views;
  std::vector<std::pair<double, int>> view_time_board;
  for (int k = 0; k < num_frames; k += stride) {
    std::vector<View> by_board(boards);
    for (size_t i = 0; i < frames.point_ids[k].size(); ++i) {
      const int id = frames.point_ids[k][i];
      for (int b = boards - 1; b >= 0; --b) {
        if (id < layouts[b].first_point) continue;
        by_board[b].points.push_back(layouts[b].corners_in_board[id - layouts[b].first_point]);
        by_board[b].pixels.push_back(frames.views[k].pixels[i]);
        break;
      }
    }
    for (int b = 0; b < boards; ++b) {
      if (by_board[b].points.size() < kMinViewPoints) continue;
      views.push_back(std::move(by_board[b]));
      view_time_board.emplace_back(frames.times_s[k], b);
    }
  }
  ZhangOptions options;
  options.model = s.zhang.model;
  options.image_width = s.image_width;
  options.image_height = s.image_height;
  const ZhangResult z = CalibrateZhang(views, options);
  if (!z.IsUsable()) return fail(z.message);

  std::vector<Rigid3> parent_from_cam_views, parent_from_points0, cam_from_board0;
  for (size_t i = 0; i < z.used_views.size(); ++i) {
    const auto [time, b] = view_time_board[z.used_views[i]];
    const Rigid3 parent_from_points = scene.ParentFromPoints(time);
    const Rigid3 parent_from_board = parent_from_points * layouts[b].points_from_board;
    parent_from_cam_views.push_back(parent_from_board * z.cam_from_board[i].Inverse());
    if (b == 0) {
      // Hand-eye sees board 0 as the target: cam_from_target with target = board 0, and the
      // points frame's motion (the board sits still in it).
      parent_from_points0.push_back(parent_from_points);
      cam_from_board0.push_back(z.cam_from_board[i] *
                                Rigid3{layouts[0].points_from_board.Inverse()});
    }
  }
  out->usable = true;
  out->intrinsics = z.intrinsics;
  out->parent_from_cam = AveragePoses(parent_from_cam_views);

  DecomposedCamera cam;
  cam.intrinsics = z.intrinsics;
  const std::string note = z.message + "; " + std::to_string(views.size()) + " views";
  for (RunRow* r : {&row, &hand_eye_row}) {
    r->status = "ok";
    r->message = note;
    r->wall_ms = z.wall_ms;
    r->rms_reproj_px = z.rms_reproj_px;
    r->std_fku = z.intrinsics_std[0];
    r->std_fkv = z.intrinsics_std[1];
    r->std_u0 = z.intrinsics_std[3];
    r->std_v0 = z.intrinsics_std[4];
  }
  cam.parent_from_cam = out->parent_from_cam;
  FillCameraErrors(s, cam, &row);
  row.theta_err_norm = ThetaErrorOf(s, z.intrinsics, cam.parent_from_cam.Inverse());

  std::string why;
  Rigid3 hand_eye;
  if (!HandEye(parent_from_points0, cam_from_board0, &hand_eye, &why)) {
    hand_eye_row.status = "failed";
    hand_eye_row.message = why;
    return {row, hand_eye_row};
  }
  cam.parent_from_cam = hand_eye;
  FillCameraErrors(s, cam, &hand_eye_row);
  hand_eye_row.theta_err_norm = ThetaErrorOf(s, z.intrinsics, hand_eye.Inverse());
  return {row, hand_eye_row};
}

}  // namespace

std::vector<std::string> EnabledMethods(const ScenarioConfig& s) {
  std::vector<std::string> methods;
  if (s.adaptive.enabled) methods.push_back("adaptive");
  if (s.dlt.enabled) methods.push_back("dlt");
  if (s.zhang.enabled) methods.insert(methods.end(), {"zhang", "zhang_handeye"});
  if (s.ceres.enabled) methods.push_back("ceres");
  return methods;
}

std::vector<RunRow> RunMethods(const ScenarioConfig& s, const SceneTruth& scene,
                               const MeasurementSource& source, const RunRow& base,
                               ScenarioShared* shared, const MethodSelection& selection) {
  std::vector<RunRow> rows;
  if (s.adaptive.enabled && selection.adaptive) {
    rows.push_back(RunAdaptive(s, source, base, selection));
  }
  if (selection.batch && (s.dlt.enabled || s.ceres.enabled || s.zhang.enabled)) {
    const FrameViews frames = ReadFrames(source);
    DltResult dlt;
    ZhangExtrinsics zhang;
    if (s.dlt.enabled || (s.ceres.enabled && s.ceres.init == "dlt")) {
      RunRow dlt_row = RunDlt(s, frames.views, base, &dlt);
      if (s.dlt.enabled) rows.push_back(dlt_row);
    }
    if (s.zhang.enabled || (s.ceres.enabled && s.ceres.init == "zhang")) {
      std::vector<RunRow> zhang_rows = RunZhang(s, scene, frames, base, &zhang);
      if (s.zhang.enabled) rows.insert(rows.end(), zhang_rows.begin(), zhang_rows.end());
    }
    if (s.ceres.enabled) rows.push_back(RunCeres(s, frames.views, dlt, zhang, shared, base));
  }
  return rows;
}

}  // namespace calibench
