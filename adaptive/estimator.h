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
// Variants that follow a calibration that changes (spec dynamic-calibration.md; Ioannou & Sun,
// Robust Adaptive Control, ch. 4; Slotine & Li, Applied Nonlinear Control, 8.7). The thesis's
// law has Gamma ~ (c t)^-1: after a change at t0 its time constant is ~ t0 / alpha, growing with
// the time it has run (windup). Each variant keeps the information form:
//   exponential forgetting (forgetting_beta = beta > 0) of the information the data brought:
//       d/dt P = -beta (P - P0) + W_bar^T W_bar,  P0 = P(0) = I / gamma0,
//       i.e. P(t) = P0 + integral e^(-beta (t - s)) W_bar^T W_bar ds: a memory of 1/beta seconds
//       (the gain alpha Gamma ~ alpha beta / c instead of alpha / (c t)). Forgetting towards P0,
//       not towards 0 (d/dt P = -beta P + W_bar^T W_bar), keeps Gamma <= gamma0 I: a direction the
//       data never excite would otherwise see Gamma grow as e^(beta t), and theta has one always
//       (W_bar(theta_hat) theta_hat = 0: M is known up to scale; measured on the rig, tr Gamma =
//       405 after 30 s at beta = 0.2, e^720 after an hour);
//   bounded-gain forgetting (also forgetting_gain_bound = k0 < inf): beta(t) = beta (1 -
//       tr(Gamma) / k0), clipped at 0 (Slotine & Li): forgetting slows as the gain approaches k0;
//   covariance resetting (reset_threshold = rho > 0): after an accepted step, if
//       lambda_min(Gamma) = 1 / lambda_max(P) <= rho, then Gamma <- gamma_r I (P <- I / gamma_r,
//       gamma_r = reset_gamma, default gamma0) and the integrator restarts there. rho < gamma_r.
//       A gamma_r below gamma0 restarts with a moderate gain: less stiff, less noise let in.
// The defaults (beta = 0, no reset) are the thesis's law, integrated exactly as before.
//
// Guard: a state where some depth W_zi theta_z_hat <= 0, or a non-finite entry, rejects the step;
// if the step then shrinks below 1e-14 (1 + t) the run stops with status kDiverged. The thesis's
// projection operator (keep W_zi theta_z_hat > 0) never fires in its simulations.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "camera/projection_matrix.h"
#include "sim/measurements.h"
#include "util/status.h"

namespace calibench {

struct AdaptiveOptions {
  double alpha = 1000.0;          // Adaptation gain (thesis default 1000; >= 100 needed).
  double gamma0 = 1.0;            // Gamma(0) = gamma0 * I (thesis: 1).
  double rtol = 1e-9;             // Integrator relative tolerance (see header comment).
  double max_step_s = 0.1;        // Upper bound on one integrator step.
  double initial_step_s = 1e-10;  // First trial step; the controller adapts it at once.
  long max_steps = 20'000'000;    // Safety cap on accepted + rejected steps.
  // Variants (see the header comment); the defaults are the thesis's law.
  double forgetting_beta = 0.0;  // beta >= 0 (1/s): exponential forgetting; 0: none.
  double forgetting_gain_bound = std::numeric_limits<double>::infinity();  // k0: bounded gain.
  double reset_threshold = 0.0;  // rho in [0, gamma_r): covariance resetting; 0: never.
  double reset_gamma = 0.0;      // gamma_r > 0: Gamma after a reset; 0: gamma0.
  bool Check(std::string* why) const;
};

struct AdaptiveSummary : MethodSummary {
  Vector16d theta_hat = Vector16d::Zero();    // Final estimate (unnormalised).
  Matrix16d information = Matrix16d::Zero();  // Integral of W_bar^T W_bar dt = P(T) - P(0).
  double final_time_s = 0.0;
  long rejected_steps = 0;
  long rhs_evaluations = 0;
  long resets = 0;  // Covariance resets (reset_threshold > 0).
};

// Called with (t, theta_hat) at t = 0 and after every accepted step.
using ThetaObserver = std::function<void(double t_s, const Vector16d& theta_hat)>;

// `stop_times_s` (ascending, optional): times inside the run at which a step must end, so that the
// observer sees theta_hat exactly there (report times); they do not restart the integrator.
AdaptiveSummary RunAdaptiveEstimator(const MeasurementSource& source, const Vector16d& theta0,
                                     const AdaptiveOptions& options,
                                     const ThetaObserver& observer = {},
                                     const std::vector<double>& stop_times_s = {});

// Persistent-excitation index of an information matrix G = integral W_bar^T W_bar dt: G is
// Jacobi-normalised (unit diagonal), restricted to the complement of the scale direction theta_hat
// (W_bar(theta_hat) theta_hat = 0 always: M is known only up to scale), and its smallest eigenvalue
// there is divided by its largest. 0: some parameter direction is not excited; 1: isotropic.
double PersistentExcitationIndex(const Matrix16d& information, const Vector16d& theta_hat);

}  // namespace calibench
