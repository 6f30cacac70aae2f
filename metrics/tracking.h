// Tracking a calibration that changes over time (spec dynamic-calibration.md, "Measuring
// tracking"): an estimate's trajectory against the truth at the same times, per change event.
//
// Quantities: the tracked entries of the metric table (metric_table.h, MetricSpec::track; their
// names TrackQuantityNames): roll, pitch, yaw of R_C in degrees (the README's Euler convention, as
// runs.csv's roll_deg, ...; an opted-in improper R_C through -R_C), and f*ku, f*kv, u0, v0 in px.
// Errors are estimate minus truth, angles wrapped to (-180, 180].
//
// A method's trajectory is what it reported to EstimateSink::OnEstimate: a piecewise-constant
// function of time (an estimate holds until the next). Sampled at report times, before its first
// report it has no value (counted as outside every tolerance).
//
// Per event k at t_k (the start at 0, then each change's start; the segment ends at the next event
// or the end of the run), per quantity q with tolerance tol_q:
//   reconverge_s  the first t - t_k after which |error_q| stays <= tol_q until the segment's end;
//                 NaN if the last sample of the segment is outside;
//   steady_err    median |error_q| over the last steady_fraction of the segment;
//   peak_err      max |error_q| over the segment.
// Consistency, for an estimate with a covariance P (camera/estimate.h's layout): NEES = e^T P^-1 e,
// with e = (true - estimate) of [f*ku, f*kv, u0, v0, dtheta] (7 dof; dtheta = Log(R_C R_C_hat^T),
// parent frame) and of dtheta alone (3 dof). Averaged over N trials it should lie in the two-sided
// 95% band of the mean of N chi-square(d) variables (ChiSquareMeanBand).
#pragma once

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "camera/estimate.h"
#include "sim/scene.h"

namespace calibench {

constexpr int kTrackQuantities = 7;
using TrackValues = std::array<double, kTrackQuantities>;
// Their names with units, in TrackValues order, from the metric table (roll_deg, ..., v0_px).
const std::array<const char*, kTrackQuantities>& TrackQuantityNames();
// Whether tracked quantity q is an angle (its errors wrap to (-180, 180]).
bool TrackQuantityIsAngle(int q);

// The quantities of a camera (intrinsics and R_C).
TrackValues TrackQuantitiesOf(const CameraIntrinsics& intrinsics, const Eigen::Matrix3d& r_c,
                              bool improper);

// 0.1 deg for the angles (Algers 2018's target, §1.2), 1 px for the intrinsics.
TrackValues DefaultTrackTolerance();

struct TrackingOptions {
  // Re-convergence tolerance per quantity (DefaultTrackTolerance).
  TrackValues tolerance = DefaultTrackTolerance();
  double steady_fraction = 0.2;  // The last part of each segment that the steady error is over.
  bool Check(std::string* why) const;
};

struct TrackPoint {
  double t_s = 0.0;
  bool valid = false;  // The method had reported an estimate by then.
  TrackValues estimate{}, truth{}, error{};
  double nees = std::numeric_limits<double>::quiet_NaN();           // 7 dof.
  double nees_rotation = std::numeric_limits<double>::quiet_NaN();  // 3 dof.
};

// A method's reported estimates over time (OnEstimate), kept compactly.
class EstimateTrack {
 public:
  void Add(double t_s, const CameraEstimate& estimate);
  bool empty() const { return entries_.empty(); }
  // The trajectory at `times` (ascending) against `truth_at(t)`.
  std::vector<TrackPoint> Sample(const std::vector<double>& times,
                                 const std::function<CameraSpec(double)>& truth_at) const;

 private:
  struct Entry {
    double t_s;
    CameraIntrinsics intrinsics;
    Eigen::Matrix3d r_c;
    bool improper;
    Eigen::MatrixXd covariance;  // Empty when the method reported none.
  };
  std::vector<Entry> entries_;
};

struct EventMetrics {
  int event = 0;     // 0: the start; k: truth change k - 1.
  int quantity = 0;  // Index into TrackQuantityNames().
  double at_s = 0.0;
  double tol = 0.0;
  double reconverge_s = std::numeric_limits<double>::quiet_NaN();
  double steady_err = std::numeric_limits<double>::quiet_NaN();
  double peak_err = std::numeric_limits<double>::quiet_NaN();
};
// Per event (start at 0, then each entry of `event_times_s`) and quantity; `end_s`: the run's end.
std::vector<EventMetrics> EvaluateEvents(const std::vector<TrackPoint>& track,
                                         const std::vector<double>& event_times_s, double end_s,
                                         const TrackingOptions& options);

// The two-sided 95% band of the mean of n independent chi-square(d) variables (n d = chi-square
// with n d degrees of freedom, divided by n).
std::pair<double, double> ChiSquareMeanBand(int n, int d);

}  // namespace calibench
