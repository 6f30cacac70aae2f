#include "adaptive/estimator.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace calibench {
namespace {

// Integrator state: column 0 = theta_hat, columns 1..16 = P = Gamma^-1 (symmetric).
using State = Eigen::Matrix<double, 16, 17>;

// Dormand-Prince 5(4) tableau (Hairer, Norsett & Wanner, Table II.5.2).
constexpr double kC[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
constexpr double kA[7][6] = {
    {0, 0, 0, 0, 0, 0},
    {1.0 / 5, 0, 0, 0, 0, 0},
    {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
    {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
    {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
// Error weights: 5th-order minus embedded 4th-order solution.
constexpr double kE[7] = {71.0 / 57600,      0,          -71.0 / 16695, 71.0 / 1920,
                          -17253.0 / 339200, 22.0 / 525, -1.0 / 40};

class AdaptiveOde {
 public:
  AdaptiveOde(const MeasurementSource& source, const AdaptiveOptions& options)
      : source_(source),
        alpha_(options.alpha),
        beta_(options.forgetting_beta),
        gain_bound_(options.forgetting_gain_bound),
        p0_(1.0 / options.gamma0) {}

  // d/dt state at (t, y) in `segment`. Returns false if a depth is <= 0 or non-finite.
  bool Derivative(double t, int segment, const State& y, State* dy) {
    ++evaluations_;
    // Held frames change only at breakpoints: measure once per segment, not at every stage.
    if (!source_.HeldWithinSegments() || segment != measured_segment_) {
      source_.Measure(t, segment, &frame_);
      measured_segment_ = segment;
    }
    const Vector16d theta = y.col(0);
    // G = W_bar^T W_bar assembled from per-point outer products X = x_bar x_bar^T:
    //   blocks (r, r) = sum X; (r, z) = -sum p_hat_r X; (z, z) = sum |p_hat|^2 X.
    Eigen::Matrix4d sum_x = Eigen::Matrix4d::Zero(), sum_zz = Eigen::Matrix4d::Zero();
    Eigen::Matrix4d sum_px[3] = {Eigen::Matrix4d::Zero(), Eigen::Matrix4d::Zero(),
                                 Eigen::Matrix4d::Zero()};
    Vector16d g = Vector16d::Zero();  // W_bar^T p_tilde.
    for (size_t i = 0; i < frame_.pixels.size(); ++i) {
      const Eigen::Vector4d x = frame_.points_in_parent[i].homogeneous();
      const double depth = theta.segment<4>(12).dot(x);
      if (!(depth > 0) || !std::isfinite(depth)) return false;
      const Eigen::Vector3d m(theta.segment<4>(0).dot(x), theta.segment<4>(4).dot(x),
                              theta.segment<4>(8).dot(x));
      const Eigen::Vector3d p_hat = m / depth;
      const Eigen::Vector3d p_tilde = frame_.pixels[i].homogeneous() - p_hat;
      const Eigen::Matrix4d xx = x * x.transpose();
      sum_x += xx;
      sum_zz += p_hat.squaredNorm() * xx;
      for (int r = 0; r < 3; ++r) {
        sum_px[r] += p_hat[r] * xx;
        g.segment<4>(4 * r) += p_tilde[r] * x;
      }
      g.segment<4>(12) -= p_hat.dot(p_tilde) * x;
    }
    Matrix16d gram = Matrix16d::Zero();
    for (int r = 0; r < 3; ++r) {
      gram.block<4, 4>(4 * r, 4 * r) = sum_x;
      gram.block<4, 4>(4 * r, 12) = -sum_px[r];
      gram.block<4, 4>(12, 4 * r) = -sum_px[r];
    }
    gram.block<4, 4>(12, 12) = sum_zz;

    // theta_dot = alpha P^-1 g with P Jacobi-scaled: P = S^-1 Ps S^-1, S = diag(P)^-1/2.
    const Matrix16d p = y.rightCols<16>();
    const Vector16d s = p.diagonal().cwiseSqrt().cwiseInverse();
    const Matrix16d ps = s.asDiagonal() * p * s.asDiagonal();
    const Eigen::LLT<Matrix16d> llt(ps);
    if (llt.info() != Eigen::Success) return false;
    dy->col(0) = alpha_ * s.cwiseProduct(llt.solve(s.cwiseProduct(g)));
    dy->rightCols<16>() = gram;
    if (beta_ > 0) {  // Forgetting: d/dt P = W_bar^T W_bar - beta(t) (P - P(0)).
      double beta = beta_;
      if (std::isfinite(gain_bound_)) {
        // tr Gamma = tr(P^-1) = sum_i s_i^2 (Ps^-1)_ii.
        const Matrix16d ps_inverse = llt.solve(Matrix16d::Identity());
        const double trace_gamma = (s.array().square() * ps_inverse.diagonal().array()).sum();
        beta *= std::max(0.0, 1.0 - trace_gamma / gain_bound_);
      }
      dy->rightCols<16>() -= beta * (p - p0_ * Matrix16d::Identity());
    }
    return dy->allFinite();
  }

  long evaluations() const { return evaluations_; }

 private:
  const MeasurementSource& source_;
  double alpha_, beta_, gain_bound_, p0_;
  Frame frame_;
  int measured_segment_ = -1;
  long evaluations_ = 0;
};

// Covariance resetting's test: lambda_min(Gamma) = 1 / lambda_max(P) <= rho. lambda_max(P) lies in
// [tr P / 16, tr P]: the eigenvalues are computed only in between.
bool NeedsReset(const State& y, double rho) {
  const Matrix16d p = y.rightCols<16>();
  const double bound = 1.0 / rho, trace = p.trace();
  if (trace < bound) return false;
  if (trace / 16 >= bound) return true;
  return Eigen::SelfAdjointEigenSolver<Matrix16d>(p, Eigen::EigenvaluesOnly).eigenvalues()[15] >=
         bound;
}

// Max over entries of |error| / scale (see estimator.h for the scales).
double ErrorNorm(const State& err, const State& y0, const State& y1, double rtol) {
  double worst = 0.0;
  for (int block = 0; block < 4; ++block) {
    const double block_scale =
        std::max(y0.col(0).segment<4>(4 * block).norm(), y1.col(0).segment<4>(4 * block).norm());
    for (int i = 4 * block; i < 4 * block + 4; ++i) {
      const double sc = rtol * (block_scale + std::max(std::abs(y0(i, 0)), std::abs(y1(i, 0))));
      worst = std::max(worst, std::abs(err(i, 0)) / sc);
    }
  }
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i <= j; ++i) {
      const double sc = rtol * std::sqrt(y1(i, 1 + i) * y1(j, 1 + j));
      worst = std::max(worst, std::abs(err(i, 1 + j)) / sc);
    }
  }
  return worst;
}

// One Dormand-Prince 5(4) step of length `step` from (t, y), k[0] = y'(t): the stages k[1..6]
// (k[6] = y'(t + step) at the 5th-order solution *y_new, first-same-as-last) and the error norm
// (ErrorNorm; infinity when a stage's depth is <= 0 or non-finite).
double DormandPrinceStep(double t, double step, int segment, const State& y, double rtol,
                         AdaptiveOde* ode, State k[7], State* y_new) {
  for (int s = 1; s < 7; ++s) {
    State ys = y;
    for (int j = 0; j < s; ++j) {
      if (kA[s][j] != 0.0) ys += (step * kA[s][j]) * k[j];
    }
    if (s == 6) *y_new = ys;  // Row 7 of the tableau is the 5th-order solution (FSAL).
    if (!ode->Derivative(t + kC[s] * step, segment, ys, &k[s])) {
      return std::numeric_limits<double>::infinity();
    }
  }
  State e = State::Zero();
  for (int s = 0; s < 7; ++s) {
    if (kE[s] != 0.0) e += (step * kE[s]) * k[s];
  }
  return ErrorNorm(e, y, *y_new, rtol);
}

// The end of the next step: the first stop time after t (stop_times_s sorted; *next_stop
// advances past those <= t), or the segment's end if that comes first.
double NextStop(const std::vector<double>& stop_times_s, double t, double segment_end,
                size_t* next_stop) {
  while (*next_stop < stop_times_s.size() && stop_times_s[*next_stop] <= t) ++*next_stop;
  return *next_stop < stop_times_s.size() && stop_times_s[*next_stop] < segment_end
             ? stop_times_s[*next_stop]
             : segment_end;
}

// The step-size controller (5th-order error, exponent 1/5, safety 0.9). After an accepted step of
// `step` (error norm err <= 1) the next grows by at most 5 and shrinks by at most 5; a step
// shortened to hit a segment end (`last`) says nothing about the next one, which keeps h.
double AcceptedStepSize(double err, double step, double h, bool last) {
  const double factor = err == 0.0 ? 5.0 : std::clamp(0.9 * std::pow(err, -0.2), 0.2, 5.0);
  return last ? std::max(h, step * factor) : step * factor;
}
// After a rejected step: shrink by 0.1..0.9, or by 4 when a stage failed (err infinite).
double RejectedStepSize(double err, double step) {
  return step * (std::isfinite(err) ? std::clamp(0.9 * std::pow(err, -0.2), 0.1, 0.9) : 0.25);
}

// Covariance resetting: P = Gamma^-1 <- I / gamma_r (reset_gamma, or gamma0 when 0).
void ResetCovariance(const AdaptiveOptions& options, State* y) {
  const double gamma_r = options.reset_gamma > 0 ? options.reset_gamma : options.gamma0;
  y->rightCols<16>() = Matrix16d::Identity() / gamma_r;
}

}  // namespace

bool AdaptiveOptions::Check(std::string* why) const {
  std::ostringstream msg;
  if (!(alpha > 0 && std::isfinite(alpha))) {
    msg << "alpha must be a positive finite gain, got " << alpha;
  } else if (!(gamma0 > 0 && std::isfinite(gamma0))) {
    msg << "gamma0 must be positive, got " << gamma0;
  } else if (!(rtol > 0 && rtol < 1e-2)) {
    msg << "rtol must lie in (0, 1e-2), got " << rtol;
  } else if (!(max_step_s > 0)) {
    msg << "max_step_s must be positive, got " << max_step_s;
  } else if (!(initial_step_s > 0 && initial_step_s <= max_step_s)) {
    msg << "initial_step_s must lie in (0, max_step_s], got " << initial_step_s;
  } else if (max_steps <= 0) {
    msg << "max_steps must be positive, got " << max_steps;
  } else if (!(forgetting_beta >= 0 && std::isfinite(forgetting_beta))) {
    msg << "forgetting_beta must be >= 0 (0: no forgetting), got " << forgetting_beta;
  } else if (!(forgetting_gain_bound > 0)) {
    msg << "forgetting_gain_bound must be > 0 (inf: unbounded), got " << forgetting_gain_bound;
  } else if (!(reset_gamma >= 0 && std::isfinite(reset_gamma))) {
    msg << "reset_gamma must be >= 0 (0: gamma0), got " << reset_gamma;
  } else if (const double target = reset_gamma > 0 ? reset_gamma : gamma0;
             !(reset_threshold >= 0 && reset_threshold < target)) {
    msg << "reset_threshold must lie in [0, " << target
        << ") (below the gain a reset sets, reset_gamma or gamma0; 0: never), got "
        << reset_threshold;
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

AdaptiveSummary RunAdaptiveEstimator(const MeasurementSource& source, const Vector16d& theta0,
                                     const AdaptiveOptions& options, const ThetaObserver& observer,
                                     const std::vector<double>& stop_times_s) {
  const SummaryClock clock;
  AdaptiveSummary summary;
  summary.theta_hat = theta0;
  auto finish = [&](MethodStatus status, const std::string& message) {
    return clock.Finish(&summary, status, message);
  };
  std::string why;
  if (!options.Check(&why)) return finish(MethodStatus::kFailed, "adaptive options: " + why);
  if (!theta0.allFinite()) return finish(MethodStatus::kFailed, "initial theta is not finite");

  AdaptiveOde ode(source, options);
  State y;
  y.col(0) = theta0;
  y.rightCols<16>() = Matrix16d::Identity() / options.gamma0;
  const Matrix16d p0 = y.rightCols<16>();
  if (observer) observer(0.0, theta0);
  double t = 0.0;
  // Ends the integration at t with the estimate reached.
  auto stop = [&](MethodStatus status, const std::string& message) {
    summary.final_time_s = t;
    summary.theta_hat = y.col(0);
    summary.rhs_evaluations = ode.evaluations();
    return finish(status, message);
  };

  const std::vector<double>& breaks = source.Breakpoints();
  State k[7];
  double h = options.initial_step_s;
  long attempts = 0;
  size_t next_stop = 0;  // Into stop_times_s.
  for (int segment = 0; segment + 1 < static_cast<int>(breaks.size()); ++segment) {
    const double segment_end = breaks[segment + 1];
    t = breaks[segment];
    if (!ode.Derivative(t, segment, y, &k[0])) {
      summary.final_time_s = t;
      summary.rhs_evaluations = ode.evaluations();
      return finish(
          MethodStatus::kDiverged,
          "a depth W_z theta_z_hat became <= 0 or non-finite at t = " + std::to_string(t) + " s");
    }
    while (t < segment_end) {
      const double t_end = NextStop(stop_times_s, t, segment_end, &next_stop);
      if (++attempts > options.max_steps) {
        summary.final_time_s = t;
        return finish(MethodStatus::kFailed, "max_steps exceeded at t = " + std::to_string(t));
      }
      const bool last = h >= t_end - t;
      const double step = last ? t_end - t : h;
      State y_new;
      const double err = DormandPrinceStep(t, step, segment, y, options.rtol, &ode, k, &y_new);
      if (err <= 1.0) {
        t = last ? t_end : t + step;
        y = y_new;
        k[0] = k[6];
        ++summary.iterations;
        if (observer) observer(t, y.col(0));
        h = std::min(options.max_step_s, AcceptedStepSize(err, step, h, last));
        if (options.reset_threshold > 0 && NeedsReset(y, options.reset_threshold)) {
          // Covariance resetting: Gamma <- gamma_r I; the system is stiff again, as at t = 0.
          ResetCovariance(options, &y);
          ++summary.resets;
          h = options.initial_step_s;
          if (t < segment_end && !ode.Derivative(t, segment, y, &k[0])) {
            return stop(MethodStatus::kDiverged,
                        "a depth W_z theta_z_hat became <= 0 at a covariance reset, t = " +
                            std::to_string(t) + " s");
          }
        }
      } else {
        ++summary.rejected_steps;
        h = RejectedStepSize(err, step);
        if (h < 1e-14 * (1.0 + t)) {
          return stop(MethodStatus::kDiverged,
                      "step size underflow at t = " + std::to_string(t) +
                          " s: a depth W_z theta_z_hat is driven to <= 0 or the state blows up");
        }
      }
    }
  }
  summary.information = y.rightCols<16>() - p0;
  return stop(MethodStatus::kOk, "");
}

double PersistentExcitationIndex(const Matrix16d& information, const Vector16d& theta_hat) {
  const Vector16d diag = information.diagonal();
  if (!(diag.minCoeff() > 0)) return 0.0;
  const Vector16d s = diag.cwiseSqrt().cwiseInverse();
  const Matrix16d normalised = s.asDiagonal() * information * s.asDiagonal();
  // In normalised coordinates the scale direction is S^-1 theta_hat.
  Vector16d u = theta_hat.cwiseQuotient(s);
  u.normalize();
  const Matrix16d proj = Matrix16d::Identity() - u * u.transpose();
  const Eigen::SelfAdjointEigenSolver<Matrix16d> eig(proj * normalised * proj);
  // Eigenvalue 0 belongs to u itself; the complement's smallest is the second smallest.
  const Vector16d& values = eig.eigenvalues();
  return std::max(0.0, values[1]) / values[15];
}

}  // namespace calibench
