// The solvers' log (calib/solver_logging.h): a trust-region step that fails to evaluate makes
// Ceres log a WARNING, a start it cannot evaluate an ERROR ("Terminating: ..."); quiet by default
// neither reaches stderr (calibench reports the failure itself), with verbose both do. The solve
// itself is unchanged (the step is retried either way).
#include "calib/solver_logging.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <string>

namespace calibench {
namespace {

// r = x - 5, undefined beyond x = 2: the first Gauss-Newton step (to 5) fails to evaluate.
struct BoundedResidual : ceres::SizedCostFunction<1, 1> {
  bool Evaluate(double const* const* x, double* r, double** jacobians) const override {
    if (x[0][0] > 2) return false;
    r[0] = x[0][0] - 5;
    if (jacobians && jacobians[0]) jacobians[0][0] = 1;
    return true;
  }
};

// Stderr of one solve from x = `start`, and its final x.
std::string SolveAndCaptureStderr(double* x, double start = 0) {
  *x = start;
  ceres::Problem problem;
  problem.AddResidualBlock(new BoundedResidual, nullptr, x);
  ceres::Solver::Options options;
  options.max_num_iterations = 20;
  ceres::Solver::Summary summary;
  testing::internal::CaptureStderr();
  ceres::Solve(options, &problem, &summary);
  return testing::internal::GetCapturedStderr();
}

TEST(SolverLogging, StepWarningsOnlyWhenVerbose) {
  double quiet_x = 0, verbose_x = 0;
  ConfigureSolverLogging("calibench_test", false);
  const std::string quiet = SolveAndCaptureStderr(&quiet_x);
  ConfigureSolverLogging("calibench_test", true);
  const std::string verbose = SolveAndCaptureStderr(&verbose_x);
  ConfigureSolverLogging("calibench_test", false);
  EXPECT_EQ(quiet.find("Step failed to evaluate"), std::string::npos) << quiet;
  EXPECT_EQ(quiet.find("InitGoogleLogging"), std::string::npos) << quiet;
  EXPECT_NE(verbose.find("Step failed to evaluate"), std::string::npos) << verbose;
  // The solver reaches the boundary's side of the minimum either way (x -> 2 from below).
  EXPECT_NEAR(quiet_x, verbose_x, 1e-12);
  EXPECT_LE(quiet_x, 2.0);
}

TEST(SolverLogging, ASolverErrorOnlyWhenVerbose) {
  double quiet_x = 0, verbose_x = 0;
  ConfigureSolverLogging("calibench_test", false);
  const std::string quiet = SolveAndCaptureStderr(&quiet_x, 3.0);  // Not evaluable: x > 2.
  ConfigureSolverLogging("calibench_test", true);
  const std::string verbose = SolveAndCaptureStderr(&verbose_x, 3.0);
  ConfigureSolverLogging("calibench_test", false);
  EXPECT_EQ(quiet, "");
  EXPECT_NE(verbose.find("Residual and Jacobian evaluation failed"), std::string::npos) << verbose;
}

}  // namespace
}  // namespace calibench
