#include "metrics/tracking.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "metrics/metric_table.h"
#include "metrics/metrics.h"

namespace calibench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Log of a rotation matrix (its rotation vector), through the nearest rotation. Not
// camera/pose.h's LogSO3: this one's last digits are what tracks.csv's NEES columns hold.
Eigen::Vector3d ProjectedLogSO3(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(ProjectToSO3(r));
  return aa.angle() * aa.axis();
}

double Nees(const Eigen::VectorXd& e, const Eigen::MatrixXd& p) {
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(p);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return kNaN;
  return e.dot(ldlt.solve(e));
}

}  // namespace

namespace {

// The tracked entries of the metric table, by their index (a table that does not cover every
// index once is a programmer error).
const std::array<const MetricSpec*, kTrackQuantities>& TrackedSpecs() {
  static const std::array<const MetricSpec*, kTrackQuantities> specs = [] {
    std::array<const MetricSpec*, kTrackQuantities> s{};
    for (const MetricSpec& m : MetricTable()) {
      if (m.track < 0) continue;
      if (m.track >= kTrackQuantities || s[m.track] != nullptr) {
        throw std::logic_error(std::string("metric table: bad track index of ") + m.name);
      }
      s[m.track] = &m;
    }
    for (const MetricSpec* m : s) {
      if (m == nullptr) throw std::logic_error("metric table: a track index is not covered");
    }
    return s;
  }();
  return specs;
}

int TrackIndex(Metric m) { return Spec(m).track; }

}  // namespace

const std::array<const char*, kTrackQuantities>& TrackQuantityNames() {
  static const std::array<const char*, kTrackQuantities> names = [] {
    std::array<const char*, kTrackQuantities> n{};
    for (int q = 0; q < kTrackQuantities; ++q) n[q] = TrackedSpecs()[q]->name;
    return n;
  }();
  return names;
}

bool TrackQuantityIsAngle(int q) {
  static const std::array<bool, kTrackQuantities> angle = [] {
    std::array<bool, kTrackQuantities> a{};
    for (int i = 0; i < kTrackQuantities; ++i) a[i] = std::string(TrackedSpecs()[i]->unit) == "deg";
    return a;
  }();
  return angle.at(q);
}

TrackValues DefaultTrackTolerance() {
  TrackValues tolerance;
  for (int q = 0; q < kTrackQuantities; ++q) tolerance[q] = TrackQuantityIsAngle(q) ? 0.1 : 1.0;
  return tolerance;
}

TrackValues TrackQuantitiesOf(const CameraIntrinsics& k, const Eigen::Matrix3d& r_c,
                              bool improper) {
  const Eigen::Vector3d rpy = RollPitchYawOfRc(r_c, improper);
  TrackValues v;
  v[TrackIndex(Metric::kRoll)] = rpy[0];
  v[TrackIndex(Metric::kPitch)] = rpy[1];
  v[TrackIndex(Metric::kYaw)] = rpy[2];
  v[TrackIndex(Metric::kFku)] = k.fku_px;
  v[TrackIndex(Metric::kFkv)] = k.fkv_px;
  v[TrackIndex(Metric::kU0)] = k.u0_px;
  v[TrackIndex(Metric::kV0)] = k.v0_px;
  return v;
}

bool TrackingOptions::Check(std::string* why) const {
  std::ostringstream msg;
  for (int q = 0; q < kTrackQuantities; ++q) {
    if (!(tolerance[q] > 0 && std::isfinite(tolerance[q]))) {
      msg << "tolerance of " << TrackQuantityNames()[q] << " must be > 0, got " << tolerance[q];
      break;
    }
  }
  if (msg.str().empty() && !(steady_fraction > 0 && steady_fraction <= 1)) {
    msg << "steady_fraction must lie in (0, 1], got " << steady_fraction;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

void EstimateTrack::Add(double t_s, const CameraEstimate& e) {
  if (!e.has_camera) return;
  entries_.push_back({t_s, e.intrinsics, e.parent_from_cam.rotation, e.improper, e.covariance});
}

std::vector<TrackPoint> EstimateTrack::Sample(
    const std::vector<double>& times, const std::function<CameraSpec(double)>& truth_at) const {
  std::vector<TrackPoint> track;
  track.reserve(times.size());
  size_t next = 0;  // entries_[next - 1] holds at time t.
  for (double t : times) {
    while (next < entries_.size() && entries_[next].t_s <= t + 1e-12) ++next;
    TrackPoint p;
    p.t_s = t;
    const CameraSpec truth = truth_at(t);
    p.truth = TrackQuantitiesOf(truth.intrinsics, truth.r_c, truth.r_c.determinant() < 0);
    p.valid = next > 0;
    if (!p.valid) {
      p.estimate.fill(kNaN);
      p.error.fill(kNaN);
      track.push_back(p);
      continue;
    }
    const Entry& e = entries_[next - 1];
    p.estimate = TrackQuantitiesOf(e.intrinsics, e.r_c, e.improper);
    for (int q = 0; q < kTrackQuantities; ++q) {
      p.error[q] = TrackQuantityIsAngle(q) ? AngleDifferenceDeg(p.estimate[q], p.truth[q])
                                           : p.estimate[q] - p.truth[q];
    }
    if (e.covariance.rows() == CameraEstimate::kCovarianceSize) {
      const Eigen::Vector3d dtheta = ProjectedLogSO3(truth.r_c * e.r_c.transpose());
      const int index[7] = {0, 1, 3, 4, 5, 6, 7};
      Eigen::VectorXd err(7);
      err << truth.intrinsics.fku_px - e.intrinsics.fku_px,
          truth.intrinsics.fkv_px - e.intrinsics.fkv_px,
          truth.intrinsics.u0_px - e.intrinsics.u0_px, truth.intrinsics.v0_px - e.intrinsics.v0_px,
          dtheta;
      Eigen::MatrixXd p7(7, 7);
      for (int a = 0; a < 7; ++a) {
        for (int b = 0; b < 7; ++b) p7(a, b) = e.covariance(index[a], index[b]);
      }
      p.nees = Nees(err, p7);
      p.nees_rotation = Nees(dtheta, e.covariance.block<3, 3>(5, 5));
    }
    track.push_back(p);
  }
  return track;
}

std::vector<EventMetrics> EvaluateEvents(const std::vector<TrackPoint>& track,
                                         const std::vector<double>& event_times_s, double end_s,
                                         const TrackingOptions& options) {
  std::vector<double> starts = {0.0};
  starts.insert(starts.end(), event_times_s.begin(), event_times_s.end());
  std::vector<EventMetrics> out;
  for (size_t k = 0; k < starts.size(); ++k) {
    const double from = starts[k];
    double to = end_s;
    for (size_t j = 0; j < starts.size(); ++j) {
      if (starts[j] > from && starts[j] < to) to = starts[j];
    }
    const double steady_from = to - options.steady_fraction * (to - from);
    for (int q = 0; q < kTrackQuantities; ++q) {
      EventMetrics m;
      m.event = static_cast<int>(k);
      m.quantity = q;
      m.at_s = from;
      m.tol = options.tolerance[q];
      std::vector<double> steady;
      double peak = -1.0;
      double last_outside = -1.0;  // Time of the last sample outside the tolerance...
      double first_after = kNaN;   // ... and of the first sample after it.
      bool any = false, pending = false;
      for (const TrackPoint& p : track) {
        if (p.t_s < from || p.t_s >= to) continue;
        any = true;
        const double error =
            p.valid ? std::abs(p.error[q]) : std::numeric_limits<double>::infinity();
        if (p.valid) peak = std::max(peak, error);
        if (p.t_s >= steady_from && p.valid) steady.push_back(error);
        if (!(error <= m.tol)) {
          last_outside = p.t_s;
          pending = true;
        } else if (pending) {
          first_after = p.t_s;
          pending = false;
        }
      }
      if (!any) continue;
      if (!pending) m.reconverge_s = last_outside < 0 ? 0.0 : first_after - from;
      if (peak >= 0) m.peak_err = peak;
      if (!steady.empty()) {
        std::sort(steady.begin(), steady.end());
        const size_t n = steady.size();
        m.steady_err = n % 2 ? steady[n / 2] : 0.5 * (steady[n / 2 - 1] + steady[n / 2]);
      }
      out.push_back(m);
    }
  }
  return out;
}

std::pair<double, double> ChiSquareMeanBand(int n, int d) {
  // Wilson-Hilferty: chi2_p(k) ~ k (1 - 2/(9k) + z_p sqrt(2/(9k)))^3, z = 1.959964 (two-sided
  // 95%); within 0.5% of the exact quantiles for k >= 10 (spec: N = 50, d = 3 -> [2.36, 3.72]).
  const double k = static_cast<double>(n) * d;
  const double z = 1.959963985;
  const double a = 1 - 2 / (9 * k), b = std::sqrt(2 / (9 * k));
  const auto quantile = [&](double zz) { return k * std::pow(a + zz * b, 3); };
  return {quantile(-z) / n, quantile(z) / n};
}

}  // namespace calibench
