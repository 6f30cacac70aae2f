#include "sim/motion.h"

#include <gtest/gtest.h>

#include "sim/scene.h"
#include "sim/synthetic.h"

namespace calibench {
namespace {

// Closed forms are evaluated to rounding: positions up to ~100 m at 240 s.
constexpr double kExactTol = 1e-12;
// The RK4 path (h = 1e-3 s) vs the closed form over 240 s, per metre of travel.
constexpr double kNumericTol = 1e-11;

TwistProfile RichProfile(TwistProfile::Frame frame) {
  TwistProfile p;
  p.v_const = {0.01, -0.13, 0.02};
  p.v_cos = {-0.5, 0.1, 0.0};
  p.v_sin = {0.0, 0.05, -0.65};
  p.w_const = {0.1, 0.2, -0.1};
  p.frequency_rad_s = 1.3;
  p.frame = frame;
  return p;
}

// Without rotation the position is the integral of v: a t + b sin(f t)/f + c (1 - cos(f t))/f.
TEST(Motion, TranslationOnlyMatchesHandIntegral) {
  TwistProfile p;
  p.v_const = {0, 0.003, 0};
  p.v_cos = {0.05, 0, 0};
  p.v_sin = {0, 0, 0.15};
  const Motion motion(p, {});
  for (double t : {0.0, 0.7, 10.0, 123.4, 240.0}) {
    const Eigen::Vector3d expected(0.05 * std::sin(t), 0.003 * t, 0.15 * (1 - std::cos(t)));
    const Rigid3 pose = motion.WorldFromBody(t);
    EXPECT_LT((pose.translation - expected).norm(), kExactTol) << "t = " << t;
    EXPECT_EQ(pose.rotation, Eigen::Matrix3d::Identity());
  }
}

// Constant rotation about z with constant body velocity along x: a circle of radius v/w.
TEST(Motion, BodyTwistWithConstantRatesDrawsACircle) {
  TwistProfile p;
  p.v_const = {2.0, 0, 0};
  p.w_const = {0, 0, 0.5};
  const Motion motion(p, {});
  for (double t : {0.3, 3.0, 17.0, 240.0}) {
    const Eigen::Vector3d expected(4.0 * std::sin(0.5 * t), 4.0 * (1 - std::cos(0.5 * t)), 0);
    EXPECT_LT((motion.WorldFromBody(t).translation - expected).norm(), kExactTol);
  }
}

class MotionFrameTest : public ::testing::TestWithParam<TwistProfile::Frame> {};

// An integration of the twist's ODE written here, independent of Motion: classic RK4 with step
// h on (R, p), body twist dR/dt = R [w]x, dp/dt = R v; spatial twist dR/dt = [w]x R,
// dp/dt = v + w x p; R re-orthonormalised after every step.
Rigid3 IntegrateTwist(const TwistProfile& p, double t_end, double h) {
  struct S {
    Eigen::Matrix3d r;
    Eigen::Vector3d x;
  };
  auto derivative = [&](double t, const S& s) {
    const Eigen::Vector3d v = p.LinearVelocity(t), w = p.AngularVelocity(t);
    if (p.frame == TwistProfile::Frame::kBody) return S{s.r * Hat(w), s.r * v};
    return S{Hat(w) * s.r, v + w.cross(s.x)};
  };
  auto add = [](const S& a, const S& b, double k) { return S{a.r + k * b.r, a.x + k * b.x}; };
  S s{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()};
  const int steps = static_cast<int>(std::lround(t_end / h));
  for (int i = 0; i < steps; ++i) {
    const double t = i * h;
    const S k1 = derivative(t, s), k2 = derivative(t + h / 2, add(s, k1, h / 2));
    const S k3 = derivative(t + h / 2, add(s, k2, h / 2)), k4 = derivative(t + h, add(s, k3, h));
    s.r += h / 6 * (k1.r + 2 * k2.r + 2 * k3.r + k4.r);
    s.x += h / 6 * (k1.x + 2 * k2.x + 2 * k3.x + k4.x);
    s.r = ProjectToSO3(s.r);
  }
  return {s.r, s.x};
}

TEST_P(MotionFrameTest, ClosedFormAgreesWithAnIndependentIntegration) {
  const TwistProfile p = RichProfile(GetParam());
  const Motion exact(p, {});
  ASSERT_TRUE(exact.is_exact());
  for (double t : {0.005, 1.0, 59.99, 120.0}) {
    const Rigid3 a = exact.WorldFromBody(t), b = IntegrateTwist(p, t, 5e-4);
    EXPECT_LT((a.rotation - b.rotation).norm(), kNumericTol) << "t = " << t;
    EXPECT_LT((a.translation - b.translation).norm(), kNumericTol * 100) << "t = " << t;
  }
}

// The thesis's point-velocity laws (appendix B.2.1) hold for both cases, by central differences
// (h = 1e-4: truncation error ~1e-9 m/s on these scales).
TEST_P(MotionFrameTest, PointVelocityLawsHold) {
  const TwistProfile p = RichProfile(GetParam());
  const Motion motion(p, {});
  const Eigen::Vector3d point(3, 22, -4);
  const double h = 1e-4;
  for (double t : {1.0, 50.0, 200.0}) {
    const Eigen::Vector3d v = p.LinearVelocity(t), w = p.AngularVelocity(t);
    if (p.frame == TwistProfile::Frame::kWorld) {  // fixed camera: x = world_from_body * point.
      auto x = [&](double s) { return motion.WorldFromBody(s) * point; };
      const Eigen::Vector3d xdot = (x(t + h) - x(t - h)) / (2 * h);
      EXPECT_LT((xdot - (v + w.cross(x(t)))).norm(), 1e-7) << "t = " << t;
    } else {  // moving camera: x = body_from_world * point.
      auto x = [&](double s) { return motion.WorldFromBody(s).Inverse() * point; };
      const Eigen::Vector3d xdot = (x(t + h) - x(t - h)) / (2 * h);
      EXPECT_LT((xdot - (-v - w.cross(x(t)))).norm(), 1e-7) << "t = " << t;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BothFrames, MotionFrameTest,
                         ::testing::Values(TwistProfile::Frame::kBody,
                                           TwistProfile::Frame::kWorld));

// Time-varying angular velocity (numeric path only): rotation stays orthonormal and obeys
// dR/dt = R [w]x to finite-difference accuracy.
TEST(Motion, TimeVaryingRotationIsIntegratedAccurately) {
  TwistProfile p = RichProfile(TwistProfile::Frame::kBody);
  p.w_cos = {0.05, 0, 0.02};
  p.w_sin = {0, -0.1, 0};
  const Motion motion(p, {});
  ASSERT_FALSE(motion.is_exact());
  const double h = 1e-4;
  for (double t : {0.5, 100.0, 239.0}) {
    const Rigid3 pose = motion.WorldFromBody(t);
    EXPECT_LT(OrthogonalityDefect(pose.rotation), 1e-11);
    const Eigen::Matrix3d rdot =
        (motion.WorldFromBody(t + h).rotation - motion.WorldFromBody(t - h).rotation) / (2 * h);
    EXPECT_LT((rdot - pose.rotation * Hat(p.AngularVelocity(t))).norm(), 1e-7);
    const Eigen::Vector3d pdot =
        (motion.WorldFromBody(t + h).translation - motion.WorldFromBody(t - h).translation) /
        (2 * h);
    EXPECT_LT((pdot - pose.rotation * p.LinearVelocity(t)).norm(), 1e-7);
  }
}

// Both cases see the same point motion for a thesis preset (the preset rule in synthetic.h).
TEST(Motion, ThesisPresetsMovePointsAlikeInBothCases) {
  for (const auto& [preset, name] : ThesisMotionNames()) {
    SceneTruth fixed, moving;
    fixed.calibration_case = CalibrationCase::kFixedCamera;
    moving.calibration_case = CalibrationCase::kMovingCamera;
    fixed.points = moving.points = ThesisFeaturePoints(10);
    fixed.motion = Motion(ThesisMotionPreset(preset, CalibrationCase::kFixedCamera), {});
    moving.motion = Motion(ThesisMotionPreset(preset, CalibrationCase::kMovingCamera), {});
    for (double t : {0.0, 1.0, 77.0, 240.0}) {
      for (int i = 0; i < 10; ++i) {
        EXPECT_LT((fixed.PointInParent(i, t) - moving.PointInParent(i, t)).norm(), 1e-11)
            << name << " t = " << t;
      }
    }
  }
}

// "small": d/dt x = [.05 cos t, .003, .15 sin t] (thesis figure B.3), integrated by hand.
TEST(Motion, SmallPresetMatchesThesisPointTrajectory) {
  SceneTruth scene;
  scene.calibration_case = CalibrationCase::kMovingCamera;
  scene.points = ThesisFeaturePoints(1);
  scene.motion = Motion(ThesisMotionPreset(ThesisMotion::kSmall, scene.calibration_case), {});
  const double t = 100.0;
  const Eigen::Vector3d expected =
      scene.points[0] + Eigen::Vector3d(0.05 * std::sin(t), 0.003 * t, 0.15 * (1 - std::cos(t)));
  EXPECT_LT((scene.PointInParent(0, t) - expected).norm(), kExactTol);
}

}  // namespace
}  // namespace calibench
