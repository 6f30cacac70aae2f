// Tracking metrics (metrics/tracking.h) on trajectories whose answers are known by construction:
// re-convergence, steady and peak errors per event; NEES of errors drawn from the reported
// covariance; the chi-square band against the spec's numbers.
#include "metrics/tracking.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "metrics/metrics.h"
#include "sim/synthetic.h"
#include "util/random.h"

namespace calibench {
namespace {

// An error trajectory of one quantity (pitch) sampled every 0.1 s: 0.3 deg until 1 s, then 0.05
// deg; a step at 5 s makes it 0.5 deg, decaying to 0.05 by 6.5 s with one excursion at 7 s.
std::vector<TrackPoint> SyntheticTrack() {
  std::vector<TrackPoint> track;
  for (int k = 0; k <= 100; ++k) {
    TrackPoint p;
    p.t_s = 0.1 * k;
    p.valid = k >= 2;  // No estimate during the first 0.2 s.
    p.error.fill(0.0);
    double e = p.t_s < 1.0 ? 0.3 : 0.05;
    if (p.t_s >= 5.0) e = p.t_s < 6.5 - 1e-9 ? 0.5 : 0.05;
    if (k == 70) e = -0.2;  // t = 7 s: out of tolerance once.
    p.error[1] = e;
    track.push_back(p);
  }
  return track;
}

TEST(Tracking, EventFiguresOfAKnownTrajectory) {
  const std::vector<EventMetrics> m =
      EvaluateEvents(SyntheticTrack(), {5.0}, 10.05, TrackingOptions());
  ASSERT_EQ(m.size(), 2u * kTrackQuantities);
  const EventMetrics& start = m[1];  // Event 0, pitch.
  EXPECT_EQ(start.event, 0);
  EXPECT_EQ(std::string(TrackQuantityNames()[start.quantity]), "pitch_deg");
  EXPECT_NEAR(start.reconverge_s, 1.0, 1e-9);  // Within 0.1 deg from the sample at 1.0 s on.
  EXPECT_NEAR(start.peak_err, 0.3, 1e-12);
  EXPECT_NEAR(start.steady_err, 0.05, 1e-12);  // Median over [4, 5).
  const EventMetrics& step = m[kTrackQuantities + 1];
  EXPECT_EQ(step.at_s, 5.0);
  EXPECT_NEAR(step.reconverge_s, 2.1, 1e-9);  // The excursion at 7 s: within from 7.1 s on.
  EXPECT_NEAR(step.peak_err, 0.5, 1e-12);
  EXPECT_NEAR(step.steady_err, 0.05, 1e-12);
  EXPECT_EQ(step.tol, 0.1);
  // A quantity whose error never settles: NaN.
  std::vector<TrackPoint> drifting = SyntheticTrack();
  for (TrackPoint& p : drifting) p.error[3] = p.t_s;  // f*ku error grows 1 px/s.
  EXPECT_TRUE(
      std::isnan(EvaluateEvents(drifting, {5.0}, 10.05, TrackingOptions())[3].reconverge_s));
}

// Estimates drawn around the truth from a covariance P, reported with P: the mean NEES over many
// draws is the number of degrees of freedom (7 and 3), within its sampling error.
TEST(Tracking, NeesOfErrorsDrawnFromTheReportedCovariance) {
  const CameraSpec truth = ThesisCamera(1);
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(11, 11);
  const double stds[11] = {0.5, 0.4, 0, 0.3, 0.3, 1e-3, 2e-3, 1.5e-3, 1e-3, 1e-3, 1e-3};
  for (int i = 0; i < 11; ++i) p(i, i) = stds[i] * stds[i];
  p(0, 1) = p(1, 0) = 0.5 * stds[0] * stds[1];  // Correlated focal lengths.
  p(5, 3) = p(3, 5) = 0.3 * stds[5] * stds[3];
  // L L^T = P on the estimated parameters (phi, index 2, has zero variance).
  const std::vector<int> free = {0, 1, 3, 4, 5, 6, 7, 8, 9, 10};
  Eigen::MatrixXd reduced(10, 10);
  for (int a = 0; a < 10; ++a) {
    for (int b = 0; b < 10; ++b) reduced(a, b) = p(free[a], free[b]);
  }
  const Eigen::MatrixXd l_reduced = reduced.llt().matrixL();
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(11, 11);
  for (int a = 0; a < 10; ++a) {
    for (int b = 0; b < 10; ++b) l(free[a], free[b]) = l_reduced(a, b);
  }
  Rng rng(11);
  EstimateTrack track;
  std::vector<double> times;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd z(11);
    for (int i = 0; i < 11; ++i) z[i] = rng.Normal();
    const Eigen::VectorXd d = l * z;  // truth - estimate.
    CameraEstimate e;
    e.has_camera = true;
    e.intrinsics = truth.intrinsics;
    e.intrinsics.fku_px -= d[0];
    e.intrinsics.fkv_px -= d[1];
    e.intrinsics.u0_px -= d[3];
    e.intrinsics.v0_px -= d[4];
    // R_true = Exp(dtheta) R_hat.
    e.parent_from_cam = {ExpSO3(-d.segment<3>(5)) * truth.r_c, truth.x_c};
    e.covariance = p;
    track.Add(k, e);
    times.push_back(k);
  }
  // NOLINTNEXTLINE(performance-no-automatic-move): truth is the test's, captured by reference.
  const std::vector<TrackPoint> points = track.Sample(times, [&](double) { return truth; });
  double nees = 0, nees_rotation = 0;
  for (const TrackPoint& q : points) nees += q.nees, nees_rotation += q.nees_rotation;
  // Mean of n chi-square(d): std sqrt(2 d / n) = 0.06 (d = 7), 0.04 (d = 3); 5 sigma.
  EXPECT_NEAR(nees / n, 7.0, 5 * std::sqrt(14.0 / n));
  EXPECT_NEAR(nees_rotation / n, 3.0, 5 * std::sqrt(6.0 / n));
}

TEST(Tracking, ChiSquareBandMatchesTheSpec) {
  // dynamic-calibration.md: N = 50: d = 1 -> [0.65, 1.43]; d = 3 -> [2.36, 3.72];
  // N = 100, d = 3 -> [2.54, 3.50].
  const auto a = ChiSquareMeanBand(50, 1), b = ChiSquareMeanBand(50, 3),
             c = ChiSquareMeanBand(100, 3);
  EXPECT_NEAR(a.first, 0.65, 0.01);
  EXPECT_NEAR(a.second, 1.43, 0.01);
  EXPECT_NEAR(b.first, 2.36, 0.01);
  EXPECT_NEAR(b.second, 3.72, 0.01);
  EXPECT_NEAR(c.first, 2.54, 0.01);
  EXPECT_NEAR(c.second, 3.50, 0.01);
}

}  // namespace
}  // namespace calibench
