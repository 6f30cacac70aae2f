// The adaptive calibration estimator of the thesis (spec "The estimator", eqs. 2.16-2.17).
//
//   p_hat_i = W_xi theta_x_hat / (W_zi theta_z_hat)     (homogeneous; 3rd entry not forced to 1)
//   p_tilde_i = p_i - p_hat_i                             (3rd entry: 1 - p_hat_i3)
//   W_bar_i = [ W_xi   -p_hat_i W_zi ] in R^{3x16};  stacked over the n points: W_bar, p_tilde
//
//   d/dt theta_hat = alpha Gamma W_bar^T p_tilde                               (2.16)
//   d/dt Gamma     = -Gamma W_bar^T W_bar Gamma,  Gamma(0) = gamma0 I            (2.17)
//
// Integration (information form): with P = Gamma^-1, (2.17) is exactly d/dt P = W_bar^T W_bar, a
// quadrature with no stiffness, and (2.16) becomes d/dt theta_hat = alpha P^-1 W_bar^T p_tilde,
// solved by a Jacobi-scaled Cholesky factorisation. The pair (theta_hat, P) is integrated with the
// Dormand-Prince 5(4) embedded Runge-Kutta pair and adaptive steps (max-norm error control:
// theta entries relative to `rtol` times their row of M, P entries relative to sqrt(P_ii P_jj)).
// Near t = 0 the system is stiff (rates ~ alpha |W_bar|^2 / z ~ 1e10 /s with the thesis's numbers);
// the step controller starts at `initial_step_s` and grows geometrically as the information builds
// up (the stiffness decays like alpha / (z t)). Steps restart at every source breakpoint (a new
// frame or noise draw). Halving rtol moves no reported figure by more than 1e-6 relative
// (tests/adaptive/estimator_test.cc and README).
//
// Guard: a state where some depth W_zi theta_z_hat <= 0, or a non-finite entry, rejects the step;
// if the step then shrinks below 1e-14 (1 + t) the run stops with status kDiverged. The thesis's
// projection operator (keep W_zi theta_z_hat > 0) never fires in its simulations.
#pragma once

#include <functional>
#include <string>

#include "core/measurements.h"
#include "core/projection_matrix.h"
#include "core/status.h"

namespace calibench {

struct AdaptiveOptions {
  double alpha = 1000.0;          // Adaptation gain (thesis default 1000; >= 100 needed).
  double gamma0 = 1.0;            // Gamma(0) = gamma0 * I (thesis: 1).
  double rtol = 1e-9;             // Integrator relative tolerance (see header comment).
  double max_step_s = 0.1;        // Upper bound on one integrator step.
  double initial_step_s = 1e-10;  // First trial step; the controller adapts it at once.
  long max_steps = 20'000'000;    // Safety cap on accepted + rejected steps.
  bool Check(std::string* why) const;
};

struct AdaptiveSummary : MethodSummary {
  Vector16d theta_hat = Vector16d::Zero();    // Final estimate (unnormalised).
  Matrix16d information = Matrix16d::Zero();  // Integral of W_bar^T W_bar dt = P(T) - P(0).
  double final_time_s = 0.0;
  long rejected_steps = 0;
  long rhs_evaluations = 0;
};

// Called with (t, theta_hat) at t = 0 and after every accepted step.
using ThetaObserver = std::function<void(double t_s, const Vector16d& theta_hat)>;

AdaptiveSummary RunAdaptiveEstimator(const MeasurementSource& source, const Vector16d& theta0,
                                     const AdaptiveOptions& options,
                                     const ThetaObserver& observer = {});

// Persistent-excitation index of an information matrix G = integral W_bar^T W_bar dt: G is
// Jacobi-normalised (unit diagonal), restricted to the complement of the scale direction theta_hat
// (W_bar(theta_hat) theta_hat = 0 always: M is known only up to scale), and its smallest eigenvalue
// there is divided by its largest. 0: some parameter direction is not excited; 1: isotropic.
double PersistentExcitationIndex(const Matrix16d& information, const Vector16d& theta_hat);

}  // namespace calibench
