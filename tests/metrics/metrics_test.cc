// The metrics against independent computations: errors of constructed estimates whose answer is
// known by construction, ||theta~|| invariances, reprojection RMS of a known pixel shift, the
// Cramer-Rao bound against a numerically differentiated Fisher information, convergence times.
#include "metrics/metrics.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

// Products of a few rotations and subtractions of values <= 1e3: ~1e-12 absolute.
constexpr double kExactTol = 1e-9;

CameraSpec Camera1() { return ThesisCamera(1); }

CameraEstimate EstimateOf(const CameraSpec& c) {
  CameraEstimate e;
  e.has_camera = true;
  e.intrinsics = c.intrinsics;
  e.parent_from_cam = c.ParentFromCam();
  e.cam_from_parent = e.parent_from_cam.Inverse();
  return e;
}

TEST(Metrics, CameraErrorsOfAKnownPerturbation) {
  const CameraSpec truth = Camera1();
  CameraSpec off = truth;
  off.intrinsics.fku_px += 1.5;
  off.intrinsics.v0_px -= 0.25;
  off.intrinsics.phi_deg += 0.1;
  // Pitch up 0.5 deg, roll 0.3 deg in the README's convention, about the parent's axes:
  // R_C' = R(rpy) R_C is not the same as adding to R_C's own angles; compare against angles
  // computed here from the matrices.
  const Eigen::Matrix3d delta = FromRollPitchYawDeg({0.3, 0.5, 0.0});
  off.r_c = delta * truth.r_c;
  off.x_c += Eigen::Vector3d(0.003, -0.004, 0);
  const CameraErrors e = CameraErrorsAgainst(EstimateOf(off), truth);
  EXPECT_NEAR(e.fku_px, 1.5, kExactTol);
  EXPECT_NEAR(e.v0_px, -0.25, kExactTol);
  EXPECT_NEAR(e.phi_deg, 0.1, kExactTol);
  EXPECT_NEAR(e.position_m, 0.005, kExactTol);
  // Geodesic: the rotation angle of delta, from its trace.
  const double angle = std::acos((delta.trace() - 1) / 2) * 180 / M_PI;
  EXPECT_NEAR(e.rotation_deg, angle, 1e-7);
  const Eigen::Vector3d a = RollPitchYawDeg(off.r_c), b = RollPitchYawDeg(truth.r_c);
  EXPECT_NEAR(e.roll_deg, AngleDifferenceDeg(a[0], b[0]), kExactTol);
  EXPECT_NEAR(e.pitch_deg, AngleDifferenceDeg(a[1], b[1]), kExactTol);
  EXPECT_NEAR(e.yaw_deg, AngleDifferenceDeg(a[2], b[2]), kExactTol);
  // No camera, no errors.
  CameraEstimate none;
  EXPECT_TRUE(std::isnan(CameraErrorsAgainst(none, truth).fku_px));
}

TEST(Metrics, AngleDifferencesWrapAround) {
  EXPECT_DOUBLE_EQ(AngleDifferenceDeg(179, -179), -2);
  EXPECT_DOUBLE_EQ(AngleDifferenceDeg(-179, 179), 2);
  EXPECT_DOUBLE_EQ(AngleDifferenceDeg(180, 0), 180);
  EXPECT_DOUBLE_EQ(AngleDifferenceDeg(-180, 0), 180);
  EXPECT_DOUBLE_EQ(AngleDifferenceDeg(10, 725), 5);  // 10 - 725 = -715 = 5 (mod 360).
}

TEST(Metrics, ThetaErrorIgnoresScaleAndSignAndMeasuresTheRest) {
  const CameraSpec truth = Camera1();
  const Vector16d theta = TrueTheta(truth);
  EXPECT_NEAR(ThetaError(theta, -3.7 * theta), 0.0, 1e-12);
  EXPECT_NEAR(ThetaError(theta, 1e-3 * theta), 0.0, 1e-12);
  // theta's third row has unit norm already (a33 = 1, proper R): a change of 2 in entry 0 of an
  // estimate with the same third row is an error of exactly 2.
  Vector16d moved = theta;
  moved[0] += 2.0;
  EXPECT_NEAR(ThetaError(theta, moved), 2.0, kExactTol);
  EXPECT_TRUE(std::isinf(ThetaError(theta, Vector16d::Zero())));
  // The camera form gives the same figure as the theta of the same camera.
  CameraEstimate e = EstimateOf(truth);
  EXPECT_NEAR(ThetaErrorOf(e, truth), 0.0, 1e-9);
  e.theta = moved;
  EXPECT_NEAR(ThetaErrorOf(e, truth), 2.0, kExactTol);
}

// Shifting u0 by 0.5 px moves every projected pixel by exactly (0.5, 0): RMS 0.5, in both forms.
TEST(Metrics, ReprojectionRmsOfAKnownShift) {
  const CameraSpec truth = Camera1();
  const std::vector<Eigen::Vector3d> points = ThesisFeaturePoints(10);
  View view;
  for (const Eigen::Vector3d& p : points) {
    Eigen::Vector2d pixel;
    ASSERT_TRUE(ProjectPoint(truth.intrinsics, truth.ParentFromCam().Inverse() * p, &pixel));
    view.points.push_back(p);
    view.pixels.push_back(pixel);
  }
  CameraSpec shifted = truth;
  shifted.intrinsics.u0_px += 0.5;
  CameraEstimate camera_form = EstimateOf(shifted);
  EXPECT_NEAR(RmsReprojectionPx(camera_form, {view, view}), 0.5, 1e-9);
  CameraEstimate linear_form;
  linear_form.theta = 4.2 * TrueTheta(shifted);  // Any scale.
  EXPECT_NEAR(RmsReprojectionPx(linear_form, {view}), 0.5, 1e-9);
  EXPECT_TRUE(std::isnan(RmsReprojectionPx(CameraEstimate(), {view})));
  // EvaluateEstimate: the method's own fit RMS wins; a diverged run has none; a reflection
  // estimated for a proper camera is flagged.
  camera_form.fit_rms_px = 0.125;
  EXPECT_EQ(EvaluateEstimate(MethodStatus::kOk, camera_form, truth, 640, 480, {view}).rms_reproj_px,
            0.125);
  EXPECT_TRUE(
      std::isnan(EvaluateEstimate(MethodStatus::kDiverged, linear_form, truth, 640, 480, {view})
                     .rms_reproj_px));
  CameraEstimate improper = EstimateOf(truth);
  improper.improper = true;
  EXPECT_NE(EvaluateEstimate(MethodStatus::kOk, improper, truth, 640, 480, {view})
                .warning.find("improper"),
            std::string::npos);
}

// The CRLB against sigma^2 (J^T J)^-1 built here by central differences of the projection with
// respect to (fku, fkv, phi, u0, v0, rotation vector, translation), inverted by LDLT.
TEST(Metrics, CramerRaoBoundMatchesANumericFisherInformation) {
  const CameraSpec truth = Camera1();
  const ThesisSimulation sim = *MakeThesisSimulation(3);
  std::vector<View> views;
  for (double t = 0; t < 240; t += 12) {
    View v;
    for (const Eigen::Vector3d& p : sim.scene.points) {
      v.points.push_back(sim.scene.ParentFromPoints(t) * p);
      v.pixels.push_back(Eigen::Vector2d::Zero());  // Not used by the bound.
    }
    views.push_back(v);
  }
  auto project = [&](const Eigen::Matrix<double, 11, 1>& x, const Eigen::Vector3d& point) {
    CameraIntrinsics k = truth.intrinsics;
    k.fku_px = x[0];
    k.fkv_px = x[1];
    k.phi_deg = x[2] * 180 / M_PI;
    k.u0_px = x[3];
    k.v0_px = x[4];
    const Rigid3 cam_from_parent = truth.ParentFromCam().Inverse();
    const Rigid3 pose{ExpSO3(x.segment<3>(5)) * cam_from_parent.rotation,
                      cam_from_parent.translation + x.segment<3>(8)};
    Eigen::Vector2d pixel;
    ProjectPoint(k, pose * point, &pixel);
    return pixel;
  };
  Eigen::Matrix<double, 11, 1> x0;
  x0 << truth.intrinsics.fku_px, truth.intrinsics.fkv_px, truth.intrinsics.phi_deg * M_PI / 180,
      truth.intrinsics.u0_px, truth.intrinsics.v0_px, 0, 0, 0, 0, 0, 0;
  Eigen::Matrix<double, 11, 11> info = Eigen::Matrix<double, 11, 11>::Zero();
  for (const View& v : views) {
    for (const Eigen::Vector3d& p : v.points) {
      Eigen::Matrix<double, 2, 11> j;
      for (int c = 0; c < 11; ++c) {
        const double h = c < 2 || (c >= 3 && c < 5) ? 1e-3 : 1e-7;
        Eigen::Matrix<double, 11, 1> a = x0, b = x0;
        a[c] += h;
        b[c] -= h;
        j.col(c) = (project(a, p) - project(b, p)) / (2 * h);
      }
      info += j.transpose() * j;
    }
  }
  const double sigma = 0.5;
  const Eigen::Matrix<double, 11, 11> cov =
      sigma * sigma * info.ldlt().solve(Eigen::Matrix<double, 11, 11>::Identity());
  Parametrisation model;
  model.shared_pose = true;
  model.estimate_skew = true;
  const CrlbStd bound = CramerRaoStd(views, truth, model, sigma);
  ASSERT_TRUE(bound.valid);
  // Central differences: ~1e-6 relative; the poses' parametrisations differ (quaternion vs
  // rotation vector), which does not change the marginal of the intrinsics.
  EXPECT_NEAR(bound.std_px[0] / std::sqrt(cov(0, 0)), 1.0, 1e-4);
  EXPECT_NEAR(bound.std_px[1] / std::sqrt(cov(1, 1)), 1.0, 1e-4);
  EXPECT_NEAR(bound.std_px[2] / (std::sqrt(cov(2, 2)) * 180 / M_PI), 1.0, 1e-4);
  EXPECT_NEAR(bound.std_px[3] / std::sqrt(cov(3, 3)), 1.0, 1e-4);
  EXPECT_NEAR(bound.std_px[4] / std::sqrt(cov(4, 4)), 1.0, 1e-4);
}

TEST(Metrics, ThetaTrackConvergenceTimeAndCurve) {
  const CameraSpec truth = Camera1();
  const Vector16d theta = TrueTheta(truth);
  Vector16d off = theta;
  off[0] += 1.0;  // ||theta~|| = 1.
  ThetaTrack::Options options;
  options.tolerance = 0.5;
  options.record_curve = true;
  options.max_samples = 3;
  ThetaTrack track(truth, options);
  track.Add(0.0, off);
  track.Add(1.0, theta);
  track.Add(2.0, off);    // Above again: the convergence time moves on.
  track.Add(3.0, theta);  // First sample after the last one above.
  track.Add(4.0, theta);
  EXPECT_EQ(track.ConvergeTimeS(), 3.0);
  const auto curve = track.Curve();
  ASSERT_EQ(curve.size(), 3u);
  EXPECT_EQ(curve.front().first, 0.0);
  EXPECT_EQ(curve[1].first, 2.0);
  EXPECT_EQ(curve.back().first, 4.0);
  ThetaTrack never(truth, options);
  never.Add(0.0, off);
  EXPECT_TRUE(std::isnan(never.ConvergeTimeS()));
  ThetaTrack always(truth, options);
  always.Add(0.0, theta);
  EXPECT_EQ(always.ConvergeTimeS(), 0.0);
}

}  // namespace
}  // namespace calibench
