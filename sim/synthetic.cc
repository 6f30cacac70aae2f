#include "sim/synthetic.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace calibench {

std::vector<Eigen::Vector3d> ThesisFeaturePoints(int count) {
  static const double kX[10] = {3, -3, 5, -4, 0, 0, 12, -5, 4, 5};
  static const double kY[10] = {22, 35, 24, 37, 25, 32, 35, 42, 23, 26};
  static const double kZ[10] = {-4, 6, 7, -1, 0, 1, 12, -1, -7, -8};
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count && i < 10; ++i) points.emplace_back(kX[i], kY[i], kZ[i]);
  return points;
}

const std::vector<std::pair<ThesisMotion, const char*>>& ThesisMotionNames() {
  static const std::vector<std::pair<ThesisMotion, const char*>> names = {
      {ThesisMotion::kNone, "none"},
      {ThesisMotion::kSmall, "small"},
      {ThesisMotion::kLarge, "large"},
      {ThesisMotion::kRotation, "rotation"},
      {ThesisMotion::kSmallRotation, "small+rotation"}};
  return names;
}

TwistProfile ThesisMotionPreset(ThesisMotion motion, CalibrationCase c) {
  TwistProfile p;  // The moving-camera body twist (v_c, w_c) first.
  const bool small = motion == ThesisMotion::kSmall || motion == ThesisMotion::kSmallRotation;
  const bool rotation = motion == ThesisMotion::kRotation || motion == ThesisMotion::kSmallRotation;
  if (small) {
    p.v_cos = Eigen::Vector3d(-0.05, 0, 0);
    p.v_const = Eigen::Vector3d(0, -0.003, 0);
    p.v_sin = Eigen::Vector3d(0, 0, -0.15);
  } else if (motion == ThesisMotion::kLarge) {
    p.v_cos = Eigen::Vector3d(-0.5, 0, 0);
    p.v_const = Eigen::Vector3d(0, -0.13, 0);
    p.v_sin = Eigen::Vector3d(0, 0, -0.65);
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

CameraIntrinsics ExampleCamera(LensFamily family, double axis_focal_px, double u0_px,
                               double v0_px) {
  const LensFamilyInfo& info = InfoOf(family);
  CameraIntrinsics k;
  k.family = family;
  k.fku_px = axis_focal_px * info.example_focal_scale;
  k.fkv_px = 1.002 * axis_focal_px * info.example_focal_scale;
  k.u0_px = u0_px, k.v0_px = v0_px;
  for (int i = 0; i < 5; ++i) {
    if (double* field = LensField(&k, info.lens_params[i])) *field = info.example_lens[i];
  }
  return k;
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
  // Drawn z, y, x, w (util/random.h: one call's arguments are never draws).
  const double z = rng->Normal(), y = rng->Normal(), x = rng->Normal(), w = rng->Normal();
  Eigen::Quaterniond q(w, x, y, z);
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

Rigid3 FacingBoardPoseAlong(const Eigen::Vector3d& tilt, const Eigen::Vector3d& board_point,
                            const Eigen::Vector3d& ray, double distance_m) {
  const Eigen::Vector3d unit = ray.normalized();
  const Eigen::Matrix3d turn =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), unit).toRotationMatrix();
  const Rigid3 facing = FacingBoardPose(tilt, board_point, Eigen::Vector3d::Zero());
  Rigid3 cam_from_board;
  cam_from_board.rotation = turn * facing.rotation;
  cam_from_board.translation = distance_m * unit - cam_from_board.rotation * board_point;
  return cam_from_board;
}

Rigid3 RandomFacingBoardPose(const Eigen::Vector3d& board_point, double off_axis_deg,
                             const FacingPoseRange& range, Rng* rng) {
  constexpr double kDeg = M_PI / 180.0;
  const double azimuth = rng->Uniform(0, 2 * M_PI),
               tilt = rng->Uniform(0, range.max_tilt_deg * kDeg);
  const double axis = rng->Uniform(0, 2 * M_PI);
  const Eigen::Vector3d turn(tilt * std::cos(axis), tilt * std::sin(axis), rng->Uniform(-0.5, 0.5));
  const Eigen::Vector3d ray(std::sin(off_axis_deg * kDeg) * std::cos(azimuth),
                            std::sin(off_axis_deg * kDeg) * std::sin(azimuth),
                            std::cos(off_axis_deg * kDeg));
  return FacingBoardPoseAlong(turn, board_point, ray, rng->Uniform(range.near_m, range.far_m));
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
    const double offset_y = rng->Uniform(-0.1, 0.1) * distance;  // y first (util/random.h).
    const Eigen::Vector3d offset(rng->Uniform(-0.1, 0.1) * distance, offset_y, distance);
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
      pixel += o.pixel_sigma_px * NormalPair<Eigen::Vector2d>(rng);
      view.points.push_back(p);
      view.pixels.push_back(pixel);
    }
    if (!inside) continue;
    out.views.push_back(std::move(view));
    out.cam_from_board.push_back(cam_from_board);
  }
  return out;
}

namespace {

// One view of MakeWideBoardViews: the board's pose (see the header comment).
Rigid3 WideBoardPose(const WideBoardOptions& o, const Eigen::Vector3d& centre, Rng* rng) {
  const double theta = o.max_angle_deg * std::sqrt(rng->Uniform(0, 1)) * M_PI / 180;
  const double azimuth = rng->Uniform(0, 2 * M_PI);
  const Eigen::Vector3d direction(std::sin(theta) * std::cos(azimuth),
                                  std::sin(theta) * std::sin(azimuth), std::cos(theta));
  const double tilt = rng->Uniform(0, o.max_tilt_deg) * M_PI / 180;
  const double tilt_axis = rng->Uniform(0, 2 * M_PI);
  const Eigen::Vector3d tilt_vector =
      tilt * Eigen::Vector3d(std::cos(tilt_axis), std::sin(tilt_axis), 0);
  const double roll = rng->Uniform(-M_PI, M_PI);
  // Facing the camera along +z, then turned onto `direction` about the camera's centre.
  const Rigid3 facing =
      FacingBoardPose(tilt_vector, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::Matrix3d turn =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), direction).toRotationMatrix();
  Rigid3 cam_from_board;
  cam_from_board.rotation = turn * facing.rotation * ExpSO3(Eigen::Vector3d(0, 0, roll));
  const double distance = o.distance_m * rng->Uniform(0.8, 1.2);
  cam_from_board.translation = distance * direction - cam_from_board.rotation * centre;
  return cam_from_board;
}

}  // namespace

SyntheticBoardViews MakeWideBoardViews(const CameraIntrinsics& intrinsics,
                                       const WideBoardOptions& o, Rng* rng) {
  SyntheticBoardViews out;
  const std::vector<Eigen::Vector3d> board = BoardPoints(o.rows, o.cols, o.spacing_m);
  const Eigen::Vector3d centre((o.cols - 1) * o.spacing_m / 2, (o.rows - 1) * o.spacing_m / 2, 0);
  const size_t min_points = std::max<size_t>(
      8,
      static_cast<size_t>(std::ceil(o.min_visible_fraction * static_cast<double>(board.size()))));
  int attempts = 0;
  while (static_cast<int>(out.views.size()) < o.num_views && attempts++ < 1000 * o.num_views) {
    const Rigid3 cam_from_board = WideBoardPose(o, centre, rng);
    View view;
    for (const Eigen::Vector3d& p : board) {
      Eigen::Vector2d pixel;
      if (!ProjectPoint(intrinsics, cam_from_board * p, &pixel) || pixel.x() < -0.5 ||
          pixel.y() < -0.5 || pixel.x() > o.image_width - 0.5 || pixel.y() > o.image_height - 0.5) {
        continue;
      }
      view.points.push_back(p);
      view.pixels.push_back(pixel + o.pixel_sigma_px * NormalPair<Eigen::Vector2d>(rng));
    }
    if (view.points.size() < min_points) continue;
    out.views.push_back(std::move(view));
    out.cam_from_board.push_back(cam_from_board);
  }
  return out;
}

BoardRigScene SwayingBoardRig() {
  BoardRigScene rig;
  for (const auto& [origin, yaw_deg] : {std::make_pair(Eigen::Vector3d(-0.9, 1.5, -0.3), 0.0),
                                        std::make_pair(Eigen::Vector3d(0.1, 1.2, -0.3), 40.0)}) {
    PlanarBoard b;
    b.rows = 8;
    b.cols = 11;
    b.spacing_m = 0.08;
    b.points_from_board = {FromRollPitchYawDeg({90, 0, yaw_deg}), origin};
    rig.layouts.push_back({b.CornersInBoard(), b.points_from_board,
                           static_cast<int>(rig.boards.size()) * b.NumCorners()});
    rig.boards.push_back(b);
  }
  SceneTruth& s = rig.scene;
  s.calibration_case = CalibrationCase::kMovingCamera;
  const CameraSpec camera = ThesisCamera(1);
  s.intrinsics = camera.intrinsics;
  s.intrinsics.phi_deg = 90;
  s.parent_from_cam = camera.ParentFromCam();
  s.points = RigCorners(rig.boards);
  s.duration_s = 60;
  TwistProfile twist;
  twist.v_sin = {0.05, 0.0, 0.03};
  twist.w_sin = {0.15, 0.0, 0.1};
  twist.w_cos = {0.0, 0.2, 0.0};
  twist.frequency_rad_s = 0.5;
  Motion::Options motion_options;
  motion_options.duration_s = s.duration_s;
  s.motion = Motion(twist, motion_options);
  return rig;
}

CameraSpec ThesisInitialGuess() {
  CameraSpec c;
  c.intrinsics = CameraIntrinsics{820, 810, 90, 320, 240};
  c.r_c << -1, 0, 0, 0, 0, 1, 0, 1, 0;
  c.x_c = Eigen::Vector3d(0, -2, 0.5);
  return c;
}

CameraSpec ThesisCamera(int camera, bool proper) {
  CameraSpec c;
  if (camera == 1) {
    c.intrinsics = CameraIntrinsics{822, 813, 87, 321, 239};
    c.r_c << -1, 0, 0, 0, 0, 1, 0, 1, 0;
    c.x_c = Eigen::Vector3d(0.4, -2.3, 0.47);
    return c;
  }
  c.intrinsics = camera == 2 ? CameraIntrinsics{745, 852, 73, 160, 120}
                             : CameraIntrinsics{810, 820, 86, 320, 240};
  c.x_c = camera == 2 ? Eigen::Vector3d(1.4, -4, -0.3) : Eigen::Vector3d(1, -4, -2);
  c.r_c << 0, 1, 0, 0, 0, 1, -1, 0, 0;  // As printed: det = -1.
  if (proper) {
    c.r_c(2, 0) = 1;
  } else {
    c.allow_improper_rotation = true;
  }
  return c;
}

std::optional<ThesisSimulation> MakeThesisSimulation(int sim, bool proper) {
  struct Row {
    CalibrationCase calibration_case;
    int camera, points;
    ThesisMotion motion;
    double alpha, noise_variance;
  };
  constexpr CalibrationCase kFixed = CalibrationCase::kFixedCamera;
  constexpr CalibrationCase kMoving = CalibrationCase::kMovingCamera;
  constexpr ThesisMotion kSmall = ThesisMotion::kSmall, kLarge = ThesisMotion::kLarge;
  static const Row kRows[17] = {{kFixed, 1, 10, kSmall, 1000, 0},
                                {kFixed, 2, 10, kSmall, 1000, 0},
                                {kMoving, 1, 10, kSmall, 1000, 0},
                                {kMoving, 2, 10, kSmall, 1000, 0},
                                {kMoving, 3, 1, kSmall, 1000, 0},
                                {kMoving, 3, 2, kSmall, 1000, 0},
                                {kMoving, 3, 5, kSmall, 1000, 0},
                                {kMoving, 3, 7, kSmall, 1000, 0},
                                {kMoving, 3, 10, kSmall, 5, 0},
                                {kMoving, 3, 10, kSmall, 50, 0},
                                {kMoving, 3, 5, kLarge, 1000, 0},
                                {kMoving, 3, 5, ThesisMotion::kRotation, 1000, 0},
                                {kMoving, 3, 5, ThesisMotion::kSmallRotation, 1000, 0},
                                {kMoving, 3, 5, ThesisMotion::kNone, 1000, 0},
                                {kMoving, 3, 10, kLarge, 1000, 0.001},
                                {kMoving, 3, 10, kLarge, 1000, 0.01},
                                {kMoving, 3, 10, kLarge, 100, 0.01}};
  if (sim < 1 || sim > 17) return std::nullopt;
  const Row& row = kRows[sim - 1];
  ThesisSimulation s;
  s.sim = sim;
  s.alpha = row.alpha;
  s.seed = 1000 + static_cast<uint64_t>(sim);
  const CameraSpec camera = ThesisCamera(row.camera, proper);
  s.scene.calibration_case = row.calibration_case;
  s.scene.intrinsics = camera.intrinsics;
  s.scene.parent_from_cam = camera.ParentFromCam();
  s.scene.allow_improper_rotation = camera.allow_improper_rotation;
  s.scene.points = ThesisFeaturePoints(row.points);
  s.scene.duration_s = 240.0;
  Motion::Options motion_options;
  motion_options.duration_s = s.scene.duration_s;
  s.scene.motion = Motion(ThesisMotionPreset(row.motion, row.calibration_case), motion_options);
  s.measurements.noise.point_sigma_m = std::sqrt(row.noise_variance);
  s.measurements.noise.pixel_sigma_px = std::sqrt(row.noise_variance);
  s.measurements.noise.hold_s = 0.1;
  return s;
}

double FocalLengthPuttingRayAt(CameraIntrinsics lens, double angle_deg, double radius_px) {
  lens.fku_px = lens.fkv_px = 1, lens.u0_px = lens.v0_px = 0, lens.phi_deg = 90;
  const double t = angle_deg * M_PI / 180;
  Eigen::Vector2d normalised;
  if (!ProjectPoint(lens, Eigen::Vector3d(std::sin(t), 0, std::cos(t)), &normalised) ||
      !(normalised.norm() > 0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return radius_px / normalised.norm();
}

}  // namespace calibench
