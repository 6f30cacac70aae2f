#include "sim/motion.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace calibench {
namespace {

constexpr double kCheckpointPeriod = 0.01;
constexpr double kRk4Step = 1e-3;
constexpr double kMinExactRate = 1e-6;  // Below this |w| (but > 0) the closed form loses digits.

// Integral of cos(c s) over [0, t]; even in c.
double IntCos(double c, double t) { return c == 0.0 ? t : std::sin(c * t) / c; }
// Integral of sin(c s) over [0, t] = (1 - cos(c t)) / c, written without cancellation; odd in c.
double IntSin(double c, double t) {
  if (c == 0.0) return 0.0;
  const double s = std::sin(0.5 * c * t);
  return 2.0 * s * s / c;
}

}  // namespace

Eigen::Vector3d TwistProfile::LinearVelocity(double t) const {
  return v_const + v_cos * std::cos(frequency_rad_s * t) + v_sin * std::sin(frequency_rad_s * t);
}
Eigen::Vector3d TwistProfile::AngularVelocity(double t) const {
  return w_const + w_cos * std::cos(frequency_rad_s * t) + w_sin * std::sin(frequency_rad_s * t);
}

bool TwistProfile::Check(std::string* why) const {
  const bool finite = v_const.allFinite() && v_cos.allFinite() && v_sin.allFinite() &&
                      w_const.allFinite() && w_cos.allFinite() && w_sin.allFinite();
  std::string msg;
  if (!finite) msg = "twist components must be finite";
  if (!std::isfinite(frequency_rad_s)) msg = "frequency_rad_s must be finite";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

Motion::Motion(const TwistProfile& profile, const Options& options)
    : profile_(profile), options_(options) {
  const double rate = profile_.w_const.norm();
  exact_ = profile_.HasConstantAngularVelocity() && (rate == 0.0 || rate >= kMinExactRate);
  if (exact_) return;
  const int num = static_cast<int>(std::ceil(options_.duration_s / kCheckpointPeriod)) + 1;
  const int substeps = static_cast<int>(std::lround(kCheckpointPeriod / kRk4Step));
  checkpoints_.reserve(num);
  State s{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()};
  checkpoints_.push_back(s);
  for (int k = 1; k < num; ++k) {
    for (int j = 0; j < substeps; ++j) {
      s = Rk4Step((k - 1) * kCheckpointPeriod + j * kRk4Step, s, kRk4Step);
    }
    checkpoints_.push_back(s);
  }
}

Motion::State Motion::Derivative(double t, const State& s) const {
  const Eigen::Vector3d v = profile_.LinearVelocity(t);
  const Eigen::Vector3d w = profile_.AngularVelocity(t);
  if (profile_.frame == TwistProfile::Frame::kBody) {
    return {s.rotation * Hat(w), s.rotation * v};
  }
  return {Hat(w) * s.rotation, v + w.cross(s.position)};
}

Motion::State Motion::Rk4Step(double t, const State& s, double h) const {
  auto add = [](const State& a, const State& d, double k) {
    return State{a.rotation + k * d.rotation, a.position + k * d.position};
  };
  const State k1 = Derivative(t, s);
  const State k2 = Derivative(t + 0.5 * h, add(s, k1, 0.5 * h));
  const State k3 = Derivative(t + 0.5 * h, add(s, k2, 0.5 * h));
  const State k4 = Derivative(t + h, add(s, k3, h));
  return {s.rotation + h / 6.0 * (k1.rotation + 2 * k2.rotation + 2 * k3.rotation + k4.rotation),
          s.position + h / 6.0 * (k1.position + 2 * k2.position + 2 * k3.position + k4.position)};
}

// Closed form for constant w. With theta = |w|, K = [w/theta]x and sigma = +1 (body) or -1
// (spatial, after factoring Exp(w t) out):  Exp(sigma w s) = I + sin(theta s) sigma K +
// (1 - cos(theta s)) K^2, and the position is an integral of Exp(sigma w s) v(s), where every
// product of sines and cosines is integrated exactly (product-to-sum formulas).
Rigid3 Motion::ClosedForm(double t) const {
  const TwistProfile& p = profile_;
  const double f = p.frequency_rad_s;
  const Eigen::Vector3d& a = p.v_const;
  const Eigen::Vector3d& b = p.v_cos;
  const Eigen::Vector3d& c = p.v_sin;
  // Integral of v(s).
  const Eigen::Vector3d int_v = a * t + b * IntCos(f, t) + c * IntSin(f, t);
  const double theta = p.w_const.norm();
  if (theta == 0.0) return {Eigen::Matrix3d::Identity(), int_v};

  const double sigma = p.frame == TwistProfile::Frame::kBody ? 1.0 : -1.0;
  const Eigen::Matrix3d k = Hat(p.w_const / theta);
  // Integral of sin(theta s) v(s) and of cos(theta s) v(s).
  const Eigen::Vector3d int_sin_v = a * IntSin(theta, t) +
                                    b * 0.5 * (IntSin(theta + f, t) + IntSin(theta - f, t)) +
                                    c * 0.5 * (IntCos(theta - f, t) - IntCos(theta + f, t));
  const Eigen::Vector3d int_cos_v = a * IntCos(theta, t) +
                                    b * 0.5 * (IntCos(theta - f, t) + IntCos(theta + f, t)) +
                                    c * 0.5 * (IntSin(theta + f, t) - IntSin(theta - f, t));
  const Eigen::Vector3d integral = int_v + sigma * (k * int_sin_v) + k * k * (int_v - int_cos_v);
  const Eigen::Matrix3d rotation = ExpSO3(p.w_const * t);
  if (sigma > 0) return {rotation, integral};
  return {rotation, rotation * integral};
}

Rigid3 Motion::WorldFromBody(double t) const {
  t = std::clamp(t, 0.0, options_.duration_s);
  if (exact_) return ClosedForm(t);
  const int k =
      std::min(static_cast<int>(t / kCheckpointPeriod), static_cast<int>(checkpoints_.size()) - 1);
  State s = checkpoints_[k];
  double time = k * kCheckpointPeriod;
  while (time < t) {
    const double h = std::min(kRk4Step, t - time);
    s = Rk4Step(time, s, h);
    time += h;
  }
  return {s.rotation, s.position};
}

}  // namespace calibench
