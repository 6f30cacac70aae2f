// Rigid body motion from a twist profile, integrated exactly where possible.
//
// Twist profile (every thesis motion is one of these):
//     v(t) = v_const + v_cos * cos(f t) + v_sin * sin(f t)        [m/s]
//     w(t) = w_const + w_cos * cos(f t) + w_sin * sin(f t)        [rad/s]
// expressed either in the body frame (body twist:   dR/dt = R [w]x,  dp/dt = R v)
// or in the world frame             (spatial twist: dR/dt = [w]x R,  dp/dt = v + w x p)
// where world_from_body(t) = {R, p} and world_from_body(0) = identity.
//
// The thesis writes its motions as feature-point velocities (appendix B.2.1):
//   fixed camera:  d/dt x = v + w x x    (a point of the body, in W)  -> spatial twist
//   moving camera: d/dt x = -v - w x x   (a world point, seen from B) -> body twist
// so a fixed-camera scenario uses Frame::kWorld and a moving-camera scenario Frame::kBody.
//
// Accuracy: when w is constant (w_cos = w_sin = 0; every thesis motion) the pose is evaluated in
// closed form (Rodrigues + exact trigonometric integrals): machine precision at any t. Otherwise
// (or for 0 < |w| < 1e-6, where the closed form loses digits) a 4th-order Runge-Kutta pass with
// step 1e-3 s stores checkpoints every 0.01 s over [0, duration]; a query integrates from the
// nearest checkpoint. Its error is below 1e-12 per unit of |v| and |w| over 240 s (motion_test).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "camera/pose.h"

namespace calibench {

struct TwistProfile {
  enum class Frame { kBody, kWorld };

  Eigen::Vector3d v_const = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_cos = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_sin = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_const = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_cos = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_sin = Eigen::Vector3d::Zero();
  double frequency_rad_s = 1.0;  // f above.
  Frame frame = Frame::kBody;

  Eigen::Vector3d LinearVelocity(double t) const;
  Eigen::Vector3d AngularVelocity(double t) const;
  bool HasConstantAngularVelocity() const { return w_cos.isZero(0) && w_sin.isZero(0); }
  bool Check(std::string* why) const;
};

class Motion {
 public:
  struct Options {
    double duration_s = 240.0;  // Poses are defined on [0, duration_s].
  };

  Motion() = default;
  Motion(const TwistProfile& profile, const Options& options);

  // world_from_body at time t in [0, duration_s]; t outside is clamped.
  Rigid3 WorldFromBody(double t) const;
  const TwistProfile& profile() const { return profile_; }
  bool is_exact() const { return exact_; }

 private:
  struct State {
    Eigen::Matrix3d rotation;
    Eigen::Vector3d position;
  };
  State Derivative(double t, const State& s) const;
  State Rk4Step(double t, const State& s, double h) const;
  Rigid3 ClosedForm(double t) const;

  TwistProfile profile_;
  Options options_;
  bool exact_ = true;
  std::vector<State> checkpoints_;  // Numeric path only: state at k * kCheckpointPeriod.
};

}  // namespace calibench
