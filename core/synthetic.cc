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

}  // namespace calibench
