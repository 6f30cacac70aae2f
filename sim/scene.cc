#include "sim/scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace calibench {

const char* ToString(CalibrationCase c) {
  return c == CalibrationCase::kFixedCamera ? "fixed_camera" : "moving_camera";
}

bool operator==(const CameraSpec& a, const CameraSpec& b) {
  return a.intrinsics == b.intrinsics && a.r_c == b.r_c && a.x_c == b.x_c &&
         a.allow_improper_rotation == b.allow_improper_rotation;
}

double CalibrationChange::Fraction(double t_s) const {
  if (t_s < from_s) return 0.0;
  if (t_s >= to_s) return 1.0;
  return (t_s - from_s) / (to_s - from_s);
}

bool CalibrationChange::Check(double duration_s, std::string* why) const {
  std::ostringstream msg;
  const bool finite = rpy_deg.allFinite() && x_m.allFinite() && std::isfinite(fku_px) &&
                      std::isfinite(fkv_px) && std::isfinite(u0_px) && std::isfinite(v0_px) &&
                      std::isfinite(phi_deg);
  if (!finite) {
    msg << "every delta must be finite";
  } else if (!(from_s >= 0 && from_s <= duration_s)) {
    msg << (kind == Kind::kStep ? "at_s" : "from_s") << " = " << from_s
        << " s is outside the run [0, " << duration_s << "] s";
  } else if (kind == Kind::kRamp && !(to_s > from_s && to_s <= duration_s)) {
    msg << "a ramp needs from_s < to_s <= duration_s (" << duration_s << " s), got [" << from_s
        << ", " << to_s << "]";
  } else if (!RotatesMount() && !ShiftsCamera() && !ChangesIntrinsics()) {
    msg << "changes nothing (give rpy_deg, x_m or an intrinsic delta)";
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

bool operator==(const CalibrationChange& a, const CalibrationChange& b) {
  return a.kind == b.kind && a.from_s == b.from_s && a.to_s == b.to_s && a.rpy_deg == b.rpy_deg &&
         a.x_m == b.x_m && a.fku_px == b.fku_px && a.fkv_px == b.fkv_px && a.u0_px == b.u0_px &&
         a.v0_px == b.v0_px && a.phi_deg == b.phi_deg;
}

bool CheckChangesDoNotOverlap(const std::vector<CalibrationChange>& changes, std::string* why) {
  using Kind = CalibrationChange::Kind;
  const auto touches = [](const CalibrationChange& c, int q) {
    switch (q) {
      case 0:
        return c.RotatesMount();
      case 1:
        return c.ShiftsCamera();
      case 2:
        return c.fku_px != 0;
      case 3:
        return c.fkv_px != 0;
      case 4:
        return c.u0_px != 0;
      case 5:
        return c.v0_px != 0;
      default:
        return c.phi_deg != 0;
    }
  };
  const char* names[7] = {
      "the mount rotation", "the position", "fku_px", "fkv_px", "u0_px", "v0_px", "phi_deg"};
  for (size_t i = 0; i < changes.size(); ++i) {
    for (size_t j = i + 1; j < changes.size(); ++j) {
      const CalibrationChange &a = changes[i], &b = changes[j];
      if (a.kind != Kind::kRamp || b.kind != Kind::kRamp) continue;
      if (!(a.from_s < b.to_s && b.from_s < a.to_s)) continue;
      for (int q = 0; q < 7; ++q) {
        if (!touches(a, q) || !touches(b, q)) continue;
        if (why) {
          std::ostringstream msg;
          msg << "changes[" << i << "] and changes[" << j << "] both ramp " << names[q]
              << " over overlapping intervals [" << a.from_s << ", " << a.to_s << "] and ["
              << b.from_s << ", " << b.to_s << "] s";
          *why = msg.str();
        }
        return false;
      }
    }
  }
  return true;
}

namespace {

void AddIntrinsicChanges(const std::vector<CalibrationChange>& changes, double t_s,
                         CameraIntrinsics* k) {
  for (const CalibrationChange& c : changes) {
    if (!c.ChangesIntrinsics()) continue;
    const double f = c.Fraction(t_s);
    k->fku_px += f * c.fku_px;
    k->fkv_px += f * c.fkv_px;
    k->u0_px += f * c.u0_px;
    k->v0_px += f * c.v0_px;
    k->phi_deg += f * c.phi_deg;
  }
}

// `pose` (a_from_cam) with the mount changes of `changes` at t (CalibrationChange).
Rigid3 ChangedMount(Rigid3 pose, const std::vector<CalibrationChange>& changes, double t_s) {
  for (const CalibrationChange& c : changes) {
    const double f = c.Fraction(t_s);
    if (f == 0.0) continue;
    if (c.RotatesMount()) pose.rotation = FromRollPitchYawDeg(f * c.rpy_deg) * pose.rotation;
    if (c.ShiftsCamera()) pose.translation += f * c.x_m;
  }
  return pose;
}

}  // namespace

CameraIntrinsics SceneTruth::IntrinsicsAt(double t_s) const {
  CameraIntrinsics k = intrinsics;
  AddIntrinsicChanges(changes, t_s, &k);
  AddIntrinsicChanges(rig_changes, t_s, &k);
  return k;
}

Rigid3 SceneTruth::ParentFromCamAt(double t_s) const {
  Rigid3 pose = ChangedMount(parent_from_cam, changes, t_s);
  if (!rig_from_cam) return pose;
  return pose * ChangedMount(*rig_from_cam, rig_changes, t_s);
}

CameraSpec SceneTruth::CameraAt(double t_s) const {
  const Rigid3 pose = ParentFromCamAt(t_s);
  return {IntrinsicsAt(t_s), pose.rotation, pose.translation, allow_improper_rotation};
}

std::vector<double> SceneTruth::ChangeTimes() const {
  std::vector<double> times;
  std::vector<CalibrationChange> all = changes;
  all.insert(all.end(), rig_changes.begin(), rig_changes.end());
  for (const CalibrationChange& c : all) {
    for (double t : {c.from_s, c.to_s}) {
      if (t > 0 && t < duration_s) times.push_back(t);
    }
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

Rigid3 SceneTruth::ParentFromPoints(double t) const {
  const Rigid3 world_from_body = motion.WorldFromBody(t);
  return calibration_case == CalibrationCase::kFixedCamera ? world_from_body
                                                           : world_from_body.Inverse();
}

Eigen::Vector3d SceneTruth::PointInParent(int i, double t) const {
  return ParentFromPoints(t) * points[i];
}

bool SceneTruth::Observe(double t, std::vector<Eigen::Vector3d>* points_in_parent,
                         std::vector<Eigen::Vector2d>* pixels, std::string* why) const {
  const Rigid3 parent_from_points = ParentFromPoints(t);
  const Rigid3 cam_from_parent = HasChanges() ? CamFromParentAt(t) : CamFromParent();
  const CameraIntrinsics camera_now = HasChanges() ? IntrinsicsAt(t) : intrinsics;
  const std::array<double, 10> params = camera_now.Params();
  points_in_parent->resize(points.size());
  pixels->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    (*points_in_parent)[i] = parent_from_points * points[i];
    const Eigen::Vector3d point_in_cam = cam_from_parent * (*points_in_parent)[i];
    if (!ProjectLens(camera_now.family, params.data(), point_in_cam.data(), (*pixels)[i].data())) {
      if (why) {
        std::ostringstream msg;
        msg << "feature point " << i << " is behind the camera at t = " << t << " s (depth "
            << point_in_cam.z() << " m)";
        *why = msg.str();
      }
      return false;
    }
  }
  return true;
}

bool SceneTruth::Check(std::string* why) const {
  std::string reason;
  if (!intrinsics.Check(&reason)) {
    if (why) *why = "camera intrinsics: " + reason;
    return false;
  }
  if (!CheckRotation(parent_from_cam.rotation, 1e-9, allow_improper_rotation, &reason)) {
    if (why) *why = "R_C: " + reason;
    return false;
  }
  if (!parent_from_cam.translation.allFinite()) {
    if (why) *why = "x_C must be finite";
    return false;
  }
  if (points.empty()) {
    if (why) *why = "at least one feature point is needed";
    return false;
  }
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      if (why) *why = "feature point " + std::to_string(i) + " is not finite";
      return false;
    }
  }
  if (!(duration_s > 0 && std::isfinite(duration_s))) {
    if (why) *why = "duration_s must be positive";
    return false;
  }
  if (!motion.profile().Check(&reason)) {
    if (why) *why = "motion: " + reason;
    return false;
  }
  for (size_t i = 0; i < changes.size(); ++i) {
    if (!changes[i].Check(duration_s, &reason)) {
      if (why) *why = "changes[" + std::to_string(i) + "]: " + reason;
      return false;
    }
  }
  if (!CheckChangesDoNotOverlap(changes, why)) return false;
  if (!rig_from_cam && !rig_changes.empty()) {
    if (why) *why = "rig_changes without rig_from_cam (a camera of no rig)";
    return false;
  }
  if (rig_from_cam && !CheckRotation(rig_from_cam->rotation, 1e-6, false, &reason)) {
    if (why) *why = "rig_from_cam: " + reason;
    return false;
  }
  for (size_t i = 0; i < rig_changes.size(); ++i) {
    if (!rig_changes[i].Check(duration_s, &reason)) {
      if (why) *why = "rig_changes[" + std::to_string(i) + "]: " + reason;
      return false;
    }
  }
  if (!CheckChangesDoNotOverlap(rig_changes, why)) return false;
  for (double t : ChangeTimes()) {  // The calibration must stay valid while it changes.
    for (double at : {t, duration_s}) {
      if (!IntrinsicsAt(at).Check(&reason)) {
        if (why) *why = "changes: the intrinsics at t = " + std::to_string(at) + " s: " + reason;
        return false;
      }
    }
  }
  return true;
}

}  // namespace calibench
