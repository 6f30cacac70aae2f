#include "methods/ekf_rig.h"

#include <ceres/jet.h>
#include <ceres/rotation.h>

#include <cmath>
#include <memory>
#include <sstream>

#include "util/status.h"

namespace calibench {
namespace {

// The local states a corner of camera c >= 1 depends on (RigEkf::Project).
constexpr int kLocalStates = 17;
using LocalJet = ceres::Jet<double, kLocalStates>;

}  // namespace

void RigEkfOptions::Visit(OptionVisitor* v) {
  camera.Visit(v);
  v->Field({"q_rel_rotation_rad2_s", "rad²/s",
            "Random-walk variance per second of each axis of every relative rotation "
            "cam_c_from_cam_0."},
           &q_rel_rotation_rad2_s);
  v->Field({"q_rel_translation_m2_s", "m²/s",
            "Random-walk variance per second of each axis of every relative translation."},
           &q_rel_translation_m2_s);
  v->Field({"p0_rel_rotation_deg", "deg",
            "Initial std of each axis of every relative rotation about the start."},
           &p0_rel_rotation_deg);
  v->Field({"p0_rel_translation_m", "m",
            "Initial std of each axis of every relative translation about the start."},
           &p0_rel_translation_m);
}

bool RigEkfOptions::Check(std::string* why) const {
  if (!camera.Check(why)) return false;
  std::ostringstream msg;
  if (!(q_rel_rotation_rad2_s >= 0 && std::isfinite(q_rel_rotation_rad2_s)) ||
      !(q_rel_translation_m2_s >= 0 && std::isfinite(q_rel_translation_m2_s))) {
    msg << "process noise q_rel_* must be >= 0 and finite, got " << q_rel_rotation_rad2_s << ", "
        << q_rel_translation_m2_s;
  } else if (!(p0_rel_rotation_deg > 0 && std::isfinite(p0_rel_rotation_deg)) ||
             !(p0_rel_translation_m > 0 && std::isfinite(p0_rel_translation_m))) {
    msg << "initial std p0_rel_* must be > 0 and finite, got " << p0_rel_rotation_deg << ", "
        << p0_rel_translation_m;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

bool RigEkf::Start(const std::vector<CameraEstimate>& starts, const RigEkfOptions& options,
                   std::string* why) {
  const auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (!options.Check(why)) return false;
  if (starts.size() < 2) {
    return fail("a rig needs at least 2 cameras, got " + std::to_string(starts.size()));
  }
  for (size_t c = 0; c < starts.size(); ++c) {
    if (!starts[c].has_camera) return fail("camera " + std::to_string(c) + " has no start");
  }
  options_ = options;
  const int n = kCameraStates * static_cast<int>(starts.size());
  x_.setZero(n);
  q_.setZero(n);
  Eigen::VectorXd p0_std(n);
  lenses_.clear();
  r_c0_nominal_.clear();
  const double deg = M_PI / 180;
  for (size_t c = 0; c < starts.size(); ++c) {
    CameraStates x, p0, q;
    options.camera.Start(starts[c], &x, &p0, &q);
    const int b = kCameraStates * static_cast<int>(c);
    lenses_.push_back(starts[c].intrinsics);
    if (c == 0) {
      r_c_nominal_ = starts[0].parent_from_cam.rotation;
      r_c0_nominal_.push_back(Eigen::Matrix3d::Identity());
    } else {
      const Rigid3 cam_c_from_cam_0 =
          starts[c].parent_from_cam.Inverse() * starts[0].parent_from_cam;
      r_c0_nominal_.push_back(cam_c_from_cam_0.rotation);
      x.segment<3>(8) = cam_c_from_cam_0.translation;
      p0.segment<3>(5).setConstant(options.p0_rel_rotation_deg * deg);
      p0.segment<3>(8).setConstant(options.p0_rel_translation_m);
      q.segment<3>(5).setConstant(options.q_rel_rotation_rad2_s);
      q.segment<3>(8).setConstant(options.q_rel_translation_m2_s);
    }
    x_.segment<kCameraStates>(b) = x;
    p0_std.segment<kCameraStates>(b) = p0;
    q_.segment<kCameraStates>(b) = q;
  }
  p_ = p0_std.array().square().matrix().asDiagonal();
  free_.clear();
  for (int i = 0; i < n; ++i) {
    if (i % kCameraStates != 2 || options.camera.estimate_skew) free_.push_back(i);
  }
  return true;
}

void RigEkf::Predict(double dt_s) { p_.diagonal() += dt_s * q_; }

int RigEkf::GlobalIndex(int c, int j) const {
  const int b = kCameraStates * c;
  if (j < 5) return b + j;  // Camera c's intrinsics.
  if (j < 11) return j;     // Camera 0's mount.
  return b + 5 + (j - 11);  // Camera c's relative pose.
}

template <typename T>
bool RigEkf::Project(int c, const T* local, const Eigen::Vector3d& point_in_parent,
                     T* pixel) const {
  T point_in_cam_0[3];
  MountPointInCam(local + 5, local + 8, r_c_nominal_, point_in_parent, point_in_cam_0);
  if (c == 0) return ProjectWithIntrinsics(local, lenses_[0], point_in_cam_0, pixel);
  // p_c = Exp(dtheta_c) R_c0_nominal p_0 + t_c.
  const Eigen::Matrix3d& r = r_c0_nominal_[c];
  T w[3];
  for (int i = 0; i < 3; ++i) {
    w[i] = T(r(i, 0)) * point_in_cam_0[0] + T(r(i, 1)) * point_in_cam_0[1] +
           T(r(i, 2)) * point_in_cam_0[2];
  }
  T point_in_cam[3];
  ceres::AngleAxisRotatePoint(local + 11, w, point_in_cam);
  for (int i = 0; i < 3; ++i) point_in_cam[i] += local[14 + i];
  return ProjectWithIntrinsics(local, lenses_[c], point_in_cam, pixel);
}

bool RigEkf::Update(const std::vector<const View*>& views_by_camera) {
  const int m = static_cast<int>(free_.size());
  std::vector<int> free_position(NumStates(), -1);
  for (int a = 0; a < m; ++a) free_position[free_[a]] = a;
  long corners = 0;
  for (int c = 0; c < NumCameras() && c < static_cast<int>(views_by_camera.size()); ++c) {
    if (views_by_camera[c] != nullptr)
      corners += static_cast<long>(views_by_camera[c]->points.size());
  }
  if (corners == 0) return false;
  const auto linearise = [&](const Eigen::VectorXd& at, const AddMeasurementRow& add) {
    Eigen::RowVectorXd h(m);
    for (int c = 0; c < NumCameras() && c < static_cast<int>(views_by_camera.size()); ++c) {
      const View* view = views_by_camera[c];
      if (view == nullptr) continue;
      const int locals = c == 0 ? kCameraStates : kLocalStates;
      LocalJet local[kLocalStates];
      std::vector<int> position(locals);
      for (int j = 0; j < locals; ++j) {
        const int g = GlobalIndex(c, j);
        local[j] = LocalJet(at[g], j);
        position[j] = free_position[g];
      }
      for (size_t i = 0; i < view->points.size(); ++i) {
        LocalJet pixel[2];
        if (!Project(c, local, view->points[i], pixel)) continue;
        for (int k = 0; k < 2; ++k) {
          h.setZero();
          for (int j = 0; j < locals; ++j) {
            if (position[j] >= 0) h[position[j]] = pixel[k].v[j];
          }
          add(h, view->pixels[i][k] - pixel[k].a);
        }
      }
    }
  };
  Eigen::VectorXd x = x_;
  Eigen::MatrixXd posterior;
  if (!InformationUpdate(p_, free_, options_.camera.pixel_sigma_px, options_.camera.iterations,
                         linearise, &x, &posterior) ||
      !x.allFinite()) {
    return false;  // A degenerate instant: keep the prediction.
  }
  x_ = x;
  p_.setZero();
  for (int a = 0; a < m; ++a) {
    for (int b = 0; b < m; ++b) p_(free_[a], free_[b]) = posterior(a, b);
  }
  // Reset the error states into the nominal rotations.
  r_c_nominal_ = ExpSO3(x_.segment<3>(5)) * r_c_nominal_;
  x_.segment<3>(5).setZero();
  for (int c = 1; c < NumCameras(); ++c) {
    const int b = kCameraStates * c + 5;
    r_c0_nominal_[c] = ExpSO3(x_.segment<3>(b)) * r_c0_nominal_[c];
    x_.segment<3>(b).setZero();
  }
  return true;
}

Rigid3 RigEkf::CamFromCam0(int c) const {
  const int b = kCameraStates * c;
  return {ProjectToSO3(ExpSO3(x_.segment<3>(b + 5)) * r_c0_nominal_[c]), x_.segment<3>(b + 8)};
}

Eigen::Matrix<double, 6, 6> RigEkf::CamFromCam0Covariance(int c) const {
  const int b = kCameraStates * c;
  return p_.block<6, 6>(b + 5, b + 5);
}

CameraEstimate RigEkf::Estimate(int c) const {
  const CameraStates x0 = x_.segment<kCameraStates>(0);
  const Eigen::Matrix3d r_c = ExpSO3(x0.segment<3>(5)) * r_c_nominal_;
  if (c == 0) return CameraEstimateOf(x0, r_c, lenses_[0], p_.topLeftCorner(11, 11));
  // parent_from_cam_c = parent_from_cam_0 * (cam_c_from_cam_0)^-1: R_Cc = R_C R_c0^T,
  // x_Cc = x_C - R_Cc t_c. To first order in the error states (dtheta_Cc in the parent frame):
  //   dtheta_Cc = dtheta_0 - R_Cc dtheta_c,
  //   dx_Cc     = dx_C + [R_Cc t_c]x dtheta_0 - R_Cc [t_c]x dtheta_c - R_Cc dt_c.
  const int b = kCameraStates * c;
  const Rigid3 cam_c_from_cam_0 = CamFromCam0(c);
  const Eigen::Matrix3d r_cc = r_c * cam_c_from_cam_0.rotation.transpose();
  const Eigen::Vector3d t_c = cam_c_from_cam_0.translation;
  CameraStates x;
  x << x_.segment<5>(b), 0, 0, 0, x0.segment<3>(8) - r_cc * t_c;
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(kCameraStates, NumStates());
  j.block<5, 5>(0, b).setIdentity();
  j.block<3, 3>(5, 5).setIdentity();
  j.block<3, 3>(5, b + 5) = -r_cc;
  j.block<3, 3>(8, 8).setIdentity();
  j.block<3, 3>(8, 5) = Hat(r_cc * t_c);
  j.block<3, 3>(8, b + 5) = -r_cc * Hat(t_c);
  j.block<3, 3>(8, b + 8) = -r_cc;
  return CameraEstimateOf(x, r_cc, lenses_[c], j * p_ * j.transpose());
}

bool RunRigEkf(const std::vector<const FrameSet*>& frames_by_camera, double after_s, RigEkf* filter,
               const std::function<void(double t_s)>& on_update, RigEkfSummary* summary,
               std::string* why) {
  constexpr double kSyncToleranceS = 1e-6;
  *summary = RigEkfSummary();
  if (static_cast<int>(frames_by_camera.size()) != filter->NumCameras()) {
    if (why)
      *why = "the filter has " + std::to_string(filter->NumCameras()) + " cameras, got " +
             std::to_string(frames_by_camera.size()) + " cameras' frames";
    return false;
  }
  const FrameSet& first = *frames_by_camera.front();
  for (size_t c = 1; c < frames_by_camera.size(); ++c) {
    const FrameSet& other = *frames_by_camera[c];
    bool synchronised = other.times_s.size() == first.times_s.size();
    for (size_t k = 0; synchronised && k < first.times_s.size(); ++k) {
      synchronised = std::abs(other.times_s[k] - first.times_s[k]) <= kSyncToleranceS;
    }
    if (!synchronised) {
      if (why) *why = "camera " + std::to_string(c) + "'s frames are not camera 0's instants";
      return false;
    }
  }
  double last_t = after_s;
  std::vector<const View*> views(frames_by_camera.size());
  for (size_t k = 0; k < first.times_s.size(); ++k) {
    const double t = first.times_s[k];
    if (t <= after_s) continue;
    filter->Predict(t - last_t);  // Random walk since the last instant.
    last_t = t;
    for (size_t c = 0; c < frames_by_camera.size(); ++c) views[c] = &frames_by_camera[c]->views[k];
    if (!filter->Update(views)) {
      ++summary->skipped;
      continue;
    }
    ++summary->updates;
    if (on_update) on_update(t);
  }
  return true;
}

namespace {

// Method `ekf_rig`: RigEkf on a rig scenario's cameras (MethodInput::rig_inputs), each camera
// started from its own `init` on the first init_window_s seconds as method ekf is. Its result and
// estimates over time are those of the input's camera (RigEkf::Estimate): camera c's
// parent_from_cam = parent_from_cam_0 * (cam_c_from_cam_0)^-1, so the rig figures of its rows are
// the filter's relative pose. Each camera's row runs the filter (deterministic: the same run).
class EkfRigMethod final : public FilterMethod<RigEkfOptions> {
 public:
  std::unique_ptr<Method> Clone() const override { return std::make_unique<EkfRigMethod>(*this); }

  MethodResult Run(const MethodInput& input, EstimateSink* sink) const override {
    const SummaryClock clock;
    MethodResult result;
    const int cameras = static_cast<int>(input.rig_inputs.size());
    if (cameras < 2) {
      return clock.Finish(&result, MethodStatus::kFailed,
                          "ekf_rig estimates a rig jointly: the scenario has no `rig:` cameras");
    }
    std::vector<CameraEstimate> starts;
    std::vector<const FrameSet*> frames;
    for (int c = 0; c < cameras; ++c) {
      const MethodInput& camera = *input.rig_inputs[c];
      if (RefuseWideLens(camera, "ekf_rig (camera " + std::to_string(c) + ")", &result)) {
        return result;
      }
      const MethodResult& init = camera.Window(0.0, start_.init_window_s).Prerequisite(start_.init);
      if (!init.IsUsable() || !init.estimate.has_camera) {
        return clock.Finish(&result, MethodStatus::kFailed,
                            "initialisation (" + start_.init + ") of camera " + std::to_string(c) +
                                " failed: " + init.message);
      }
      starts.push_back(init.estimate);
      frames.push_back(&camera.Frames());
    }
    RigEkf filter;
    std::string why;
    if (!filter.Start(starts, filter_, &why)) {
      return clock.Finish(&result, MethodStatus::kFailed, why);
    }
    const int mine = input.rig_camera;
    RigEkfSummary summary;
    const auto report = [&](double t) {
      if (sink != nullptr) sink->OnEstimate(t, filter.Estimate(mine));
    };
    if (!RunRigEkf(frames, start_.init_window_s, &filter, report, &summary, &why)) {
      return clock.Finish(&result, MethodStatus::kFailed, why);
    }
    result.iterations = summary.updates;
    if (summary.updates == 0) {
      return clock.Finish(&result, MethodStatus::kFailed,
                          "no instant after init_window_s = " +
                              std::to_string(start_.init_window_s) + " s updated the filter");
    }
    result.estimate = filter.Estimate(mine);
    std::ostringstream note;
    note << summary.updates << " updates of " << cameras << " cameras jointly";
    if (summary.skipped > 0) note << ", " << summary.skipped << " instants skipped";
    return clock.Finish(&result, MethodStatus::kOk, note.str());
  }
};

}  // namespace

std::unique_ptr<Method> MakeEkfRigMethod() { return std::make_unique<EkfRigMethod>(); }

}  // namespace calibench
