// The solvers' log (Ceres writes through glog): initialised once, quiet by default.
//
// Without --verbose only glog's FATAL lines reach stderr. Ceres's WARNING lines ("Step failed to
// evaluate. Treating it as a step with infinite cost": a trial step the trust region shrinks and
// retries, not an error), its ERROR lines ("Terminating: Residual and Jacobian evaluation
// failed.", which the solver's summary repeats) and its per-iteration VLOG(1) lines are hidden; a
// real failure reaches the user as calibench's own one-line message (the method's status and
// reason, naming the view it is traced to: batch/refine.h failed_view).
// With --verbose every glog line is shown, per-iteration lines included. glog is initialised on
// the first call, so its "Logging before InitGoogleLogging()" notice never appears.
#pragma once

namespace calibench {

// `program`: argv[0] (glog's log prefix). Safe to call again to change the verbosity.
void ConfigureSolverLogging(const char* program, bool verbose);

}  // namespace calibench
