#include "core/synthetic.h"

namespace calibench {

std::vector<Eigen::Vector3d> ThesisFeaturePoints(int count) {
  static const double kX[10] = {3, -3, 5, -4, 0, 0, 12, -5, 4, 5};
  static const double kY[10] = {22, 35, 24, 37, 25, 32, 35, 42, 23, 26};
  static const double kZ[10] = {-4, 6, 7, -1, 0, 1, 12, -1, -7, -8};
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count && i < 10; ++i) points.emplace_back(kX[i], kY[i], kZ[i]);
  return points;
}

std::vector<std::string> ThesisMotionPresetNames() {
  return {"none", "small", "large", "rotation", "small+rotation"};
}

std::optional<TwistProfile> ThesisMotionPreset(const std::string& name, CalibrationCase c) {
  TwistProfile p;  // The moving-camera body twist (v_c, w_c) first.
  const bool small = name == "small" || name == "small+rotation";
  const bool rotation = name == "rotation" || name == "small+rotation";
  if (small) {
    p.v_cos = Eigen::Vector3d(-0.05, 0, 0);
    p.v_const = Eigen::Vector3d(0, -0.003, 0);
    p.v_sin = Eigen::Vector3d(0, 0, -0.15);
  } else if (name == "large") {
    p.v_cos = Eigen::Vector3d(-0.5, 0, 0);
    p.v_const = Eigen::Vector3d(0, -0.13, 0);
    p.v_sin = Eigen::Vector3d(0, 0, -0.65);
  } else if (name != "none" && !rotation) {
    return std::nullopt;
  }
  if (rotation) p.w_const = Eigen::Vector3d(0.1, 0.2, -0.1);
  p.frame = TwistProfile::Frame::kBody;
  if (c == CalibrationCase::kFixedCamera) {
    p.frame = TwistProfile::Frame::kWorld;
    for (Eigen::Vector3d* v : {&p.v_const, &p.v_cos, &p.v_sin, &p.w_const, &p.w_cos, &p.w_sin}) {
      *v = -*v;
    }
  }
  return p;
}

CameraIntrinsics RandomIntrinsics(const RandomCameraOptions& o, Rng* rng) {
  CameraIntrinsics k;
  k.fku_px = rng->Uniform(o.min_focal_px, o.max_focal_px);
  k.fkv_px = rng->Uniform(o.min_focal_px, o.max_focal_px);
  k.phi_deg = rng->Uniform(o.min_phi_deg, o.max_phi_deg);
  k.u0_px = rng->Uniform(-o.max_principal_offset_px, o.max_principal_offset_px);
  k.v0_px = rng->Uniform(-o.max_principal_offset_px, o.max_principal_offset_px);
  return k;
}

Eigen::Matrix3d RandomRotation(Rng* rng) {
  Eigen::Quaterniond q(rng->Normal(), rng->Normal(), rng->Normal(), rng->Normal());
  q.normalize();
  return q.toRotationMatrix();
}

Rigid3 RandomPose(double max_translation_m, Rng* rng) {
  Rigid3 pose;
  pose.rotation = RandomRotation(rng);
  for (int i = 0; i < 3; ++i) pose.translation[i] = rng->Uniform(-1, 1) * max_translation_m;
  return pose;
}

std::vector<Eigen::Vector3d> BoardPoints(int rows, int cols, double spacing_m) {
  std::vector<Eigen::Vector3d> points;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) points.emplace_back(c * spacing_m, r * spacing_m, 0.0);
  }
  return points;
}

Rigid3 FacingBoardPose(const Eigen::Vector3d& tilt, const Eigen::Vector3d& board_point,
                       const Eigen::Vector3d& point_in_cam) {
  Rigid3 cam_from_board;
  cam_from_board.rotation = Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()) * ExpSO3(tilt);
  cam_from_board.translation = point_in_cam - cam_from_board.rotation * board_point;
  return cam_from_board;
}

BoardView SixByFiveTagGrid() {
  BoardView b;
  b.grid.tag_rows = 5;
  b.grid.tag_cols = 6;
  b.grid.tag_size_m = 0.04;
  b.family = TagFamily::Create("tag36h11", nullptr);
  return b;
}

SyntheticBoardViews MakeBoardViews(const CameraIntrinsics& intrinsics,
                                   const SyntheticBoardOptions& o, Rng* rng) {
  SyntheticBoardViews out;
  const std::vector<Eigen::Vector3d> board = BoardPoints(o.rows, o.cols, o.spacing_m);
  const Eigen::Vector3d centre((o.cols - 1) * o.spacing_m / 2, (o.rows - 1) * o.spacing_m / 2, 0);
  int attempts = 0;
  while (static_cast<int>(out.views.size()) < o.num_views && attempts++ < 100 * o.num_views) {
    // Board tilted about a random in-plane axis, centred in front of the camera, slightly offset.
    const double axis_angle = rng->Uniform(0, 2 * M_PI);
    const double tilt = rng->Uniform(-o.max_tilt_deg, o.max_tilt_deg) * M_PI / 180;
    const Eigen::Vector3d axis(std::cos(axis_angle), std::sin(axis_angle), 0);
    const double distance = o.distance_m * rng->Uniform(0.8, 1.2);
    Rigid3 cam_from_board;
    cam_from_board.rotation =
        ExpSO3(tilt * axis) * ExpSO3(Eigen::Vector3d(0, 0, rng->Uniform(-0.3, 0.3)));
    const Eigen::Vector3d offset(rng->Uniform(-0.1, 0.1) * distance,
                                 rng->Uniform(-0.1, 0.1) * distance, distance);
    cam_from_board.translation = offset - cam_from_board.rotation * centre;
    View view;
    bool inside = true;
    for (const Eigen::Vector3d& p : board) {
      Eigen::Vector2d pixel;
      if (!ProjectPoint(intrinsics, cam_from_board * p, &pixel) || pixel.x() < -0.5 ||
          pixel.y() < -0.5 || pixel.x() > o.image_width - 0.5 || pixel.y() > o.image_height - 0.5) {
        inside = false;
        break;
      }
      pixel += o.pixel_sigma_px * Eigen::Vector2d(rng->Normal(), rng->Normal());
      view.points.push_back(p);
      view.pixels.push_back(pixel);
    }
    if (!inside) continue;
    out.views.push_back(std::move(view));
    out.cam_from_board.push_back(cam_from_board);
  }
  return out;
}

}  // namespace calibench
