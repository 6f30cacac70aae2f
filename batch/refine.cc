#include "batch/refine.h"

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>

#include "batch/board_pose.h"
#include "batch/refine_internal.h"
#include "batch/reprojection_error.h"

namespace calibench {
namespace {

using refine_internal::CovarianceOfIntrinsics;
using refine_internal::JointCovariance;
using refine_internal::Parameters;
using refine_internal::PerViewIntrinsicsCovariance;

constexpr int kN = PinholeSkewCamera::kNumParams;
// Above this many residuals a shared-pose bound (IntrinsicsCovarianceAt) takes the normal
// equations instead of ceres::Covariance's dense SVD: every default sweep's trial (<= 32k) stays on
// the reference computation, a dynamic scenario's (180 s at 20 Hz: 1.15M) does not.
constexpr int kTallProblemResiduals = 200'000;

// The hand-written Jacobians (batch/projection_jacobian.h) cover every family; autodiff asks for
// the ceres::Jet reference.
bool AnalyticJacobians(const RefineOptions& o) { return !o.autodiff; }

// The intrinsics kept at their value: the model's (FixedIntrinsics) and the caller's extra ones.
std::vector<int> FixedOf(const RefineOptions& o) {
  std::vector<int> fixed = FixedIntrinsics(o.model, o.estimate_skew);
  for (int i : o.extra_fixed_intrinsics) {
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) fixed.push_back(i);
  }
  std::sort(fixed.begin(), fixed.end());
  return fixed;
}

// The ranges of the omnidirectional families' fields (camera/camera.h, CameraIntrinsics::Check) as
// Ceres bounds on the intrinsics block: a step that would leave them is projected back onto them.
// Open ends (beta > 0, the double sphere's xi > -1) stay kOpenBoundMargin inside.
constexpr double kOpenBoundMargin = 1e-9;
constexpr double kNoBound = std::numeric_limits<double>::infinity();
struct LensBound {
  int index;  // Raw slot.
  double lower, upper;
};
// From the family's LensFamilyInfo::ranges (unified: xi >= 0; eucm: alpha in [0, 1], beta > 0;
// double-sphere: xi > -1, alpha in [0, 1]).
std::vector<LensBound> LensBounds(LensFamily family) {
  const LensFamilyInfo& info = InfoOf(family);
  std::vector<LensBound> bounds;
  for (const LensParamRange& range : info.ranges) {
    if (range.name == nullptr) continue;
    for (int i = 0; i < 5; ++i) {
      if (std::string(info.lens_params[i]) != range.name) continue;
      bounds.push_back({5 + i, range.lower_open ? range.lower + kOpenBoundMargin : range.lower,
                        range.upper == kNoUpperBound ? kNoBound : range.upper});
    }
  }
  return bounds;
}

void SetLensBounds(LensFamily family, double* intrinsics, ceres::Problem* problem) {
  for (const LensBound& b : LensBounds(family)) {
    problem->SetParameterLowerBound(intrinsics, b.index, b.lower);
    if (b.upper != kNoBound) problem->SetParameterUpperBound(intrinsics, b.index, b.upper);
  }
}

// An optimum on a bound is reached slowly: Ceres approaches it geometrically (measured on a
// unified lens whose best xi is 0: the distance to the bound shrinking by ~0.85 an iteration, 62
// iterations or 200 without converging against 8-22 off the bound). BoundWatch ends the solve
// when a free bounded intrinsic heads for its bound: it sits on it for kBoundIterations accepted
// steps, or the Aitken extrapolation of its distance d to the bound, d - D q / (1 - q) with D the
// last decrease and q = D / (the one before), falls below kAitkenShare d for kBoundIterations
// accepted steps in a row (an interior optimum, where d converges to d* > 0, extrapolates to d*).
// RefineCalibration then holds it on the bound (an active bound) and solves again without it,
// unless the cost falls off the bound (CostFallsInside), where it is freed again.
constexpr int kBoundIterations = 3;
constexpr double kAitkenShare = 0.1;
class BoundWatch final : public ceres::IterationCallback {
 public:
  BoundWatch(const double* intrinsics, std::vector<LensBound> bounds)
      : intrinsics_(intrinsics), bounds_(std::move(bounds)), tracks_(bounds_.size()) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (!summary.step_is_successful) return ceres::SOLVER_CONTINUE;
    for (size_t b = 0; b < bounds_.size(); ++b) {
      const double x = intrinsics_[bounds_[b].index];
      if (tracks_[b].Update(std::min(x - bounds_[b].lower, bounds_[b].upper - x))) {
        hit_ = bounds_[b].index;
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
    }
    return ceres::SOLVER_CONTINUE;
  }
  int hit() const { return hit_; }  // The raw slot heading for its bound, or -1.

 private:
  // The last distances to the bound and how many accepted steps in a row pointed onto it.
  struct Track {
    double d1 = -1, d2 = -1;  // The previous distance, the one before.
    int count = 0;
    bool Update(double d) {
      bool heading = d == 0;
      if (!heading && d1 > d && d2 > d1) {
        const double step = d1 - d, q = step / (d2 - d1);
        heading = q < 1 && d - step * q / (1 - q) < kAitkenShare * d;
      }
      count = heading ? count + 1 : 0;
      d2 = d1, d1 = d;
      return count >= kBoundIterations;
    }
  };
  const double* intrinsics_;
  std::vector<LensBound> bounds_;
  std::vector<Track> tracks_;
  int hit_ = -1;
};

// Builds the problem over `params`; returns the number of residual blocks (points).
int BuildProblem(const std::vector<View>& views, const RefineOptions& options, Parameters* params,
                 ceres::Problem* problem) {
  int points = 0;
  // Per-view blocks for plain least squares (same cost, less overhead); per-point blocks for a
  // robust loss (it must act on each point) and for the autodiff reference.
  const bool per_view = options.loss == RobustLoss::kNone && AnalyticJacobians(options);
  const LensFamily family = FamilyOf(options.model);
  for (size_t v = 0; v < views.size(); ++v) {
    const size_t pose = options.shared_pose ? 0 : v;
    double* blocks[3] = {params->intrinsics.data(), params->rotations[pose].data(),
                         params->translations[pose].data()};
    points += static_cast<int>(views[v].points.size());
    if (views[v].points.empty()) continue;
    if (per_view) {
      problem->AddResidualBlock(
          new ViewReprojectionCostFunction(views[v].points, views[v].pixels, family), nullptr,
          blocks, 3);
      continue;
    }
    for (size_t i = 0; i < views[v].points.size(); ++i) {
      ceres::CostFunction* cost =
          AnalyticJacobians(options)
              ? new ReprojectionCostFunction(views[v].pixels[i], views[v].points[i], family)
              : ReprojectionError::Create(views[v].pixels[i], views[v].points[i], family);
      problem->AddResidualBlock(
          cost, refine_internal::MakeLoss(options.loss, options.loss_scale_px), blocks, 3);
    }
  }
  const std::vector<int> fixed = FixedOf(options);
  if (options.fix_intrinsics) {
    problem->SetParameterBlockConstant(params->intrinsics.data());
  } else {
    if (!fixed.empty()) {
      problem->SetManifold(params->intrinsics.data(), new ceres::SubsetManifold(kN, fixed));
    }
    SetLensBounds(family, params->intrinsics.data(), problem);
  }
  for (auto& q : params->rotations)
    problem->SetManifold(q.data(), new ceres::EigenQuaternionManifold);
  return points;
}

ceres::Solver::Options SolverOptions(const RefineOptions& options) {
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = !options.shared_pose       ? ceres::DENSE_SCHUR
                                      : options.normal_equations ? ceres::DENSE_NORMAL_CHOLESKY
                                                                 : ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  // Relative cost change 1e-10: parameters settle to ~1e-5 of their noise std (noisy data); the
  // parameter tolerance ends noise-free problems, whose cost goes to zero.
  solver_options.function_tolerance = 1e-10;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-10;
  solver_options.num_threads = 1;
  // Calibration from a closed-form start is well posed: start LM near Gauss-Newton (4 iterations
  // instead of 7 on the 50-view benchmark, same optimum); rejected steps still shrink the region.
  solver_options.initial_trust_region_radius = 1e6;
  return solver_options;
}

// One solve of the problem `options` builds over *params.
struct Solved {
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Summary summary;
  int points = 0;
  long iterations = 0;  // Over every solve that led here.
  int bound_hit = -1;   // The raw slot BoundWatch stopped on, or -1.
};
Solved SolveOnce(const std::vector<View>& views, const RefineOptions& options, Parameters* params,
                 bool watch_bounds) {
  Solved out;
  out.problem = std::make_unique<ceres::Problem>();
  out.points = BuildProblem(views, options, params, out.problem.get());
  ceres::Solver::Options solver_options = SolverOptions(options);
  const std::vector<int> fixed = FixedOf(options);
  std::vector<LensBound> free_bounds;
  for (const LensBound& b : LensBounds(FamilyOf(options.model))) {
    if (std::find(fixed.begin(), fixed.end(), b.index) == fixed.end()) free_bounds.push_back(b);
  }
  BoundWatch watch(params->intrinsics.data(), free_bounds);
  if (watch_bounds && !free_bounds.empty() && !options.fix_intrinsics) {
    solver_options.callbacks.push_back(&watch);
    solver_options.update_state_every_iteration = true;  // The watch reads the parameters.
  }
  ceres::Solve(solver_options, out.problem.get(), &out.summary);
  out.iterations = static_cast<long>(out.summary.iterations.size());
  out.bound_hit = watch.hit();
  return out;
}

// Whether the cost falls when the held intrinsic `index` moves off its bound into the range (the
// others as they are): then the bound is not active after all.
bool CostFallsInside(ceres::Problem* problem, double* intrinsics, int index, LensFamily family) {
  double on_bound = 0, inside = 0;
  const double saved = intrinsics[index];
  for (const LensBound& b : LensBounds(family)) {
    if (b.index != index) continue;
    constexpr double kStep = 1e-6;
    intrinsics[index] = saved == b.lower ? saved + kStep : saved - kStep;
    problem->Evaluate(ceres::Problem::EvaluateOptions(), &inside, nullptr, nullptr, nullptr);
  }
  intrinsics[index] = saved;
  problem->Evaluate(ceres::Problem::EvaluateOptions(), &on_bound, nullptr, nullptr, nullptr);
  return inside < on_bound;
}

// SolveOnce watching the bounds; when an intrinsic sat on its bound (BoundWatch), solved again
// with it held there (*effective: the options of that last solve; *note says so), unless the
// cost falls off the bound, where it is freed again.
Solved SolveRespectingBounds(const std::vector<View>& views, const RefineOptions& options,
                             Parameters* params, RefineOptions* effective, std::string* note) {
  *effective = options;
  Solved first = SolveOnce(views, options, params, true);
  if (first.bound_hit < 0) return first;
  const int index = first.bound_hit;
  const LensFamily family = FamilyOf(options.model);
  const Parameters before = *params;
  for (const LensBound& b : LensBounds(family)) {  // Onto the bound it heads for.
    if (b.index != index) continue;
    double& x = params->intrinsics[index];
    x = x - b.lower < b.upper - x ? b.lower : b.upper;
  }
  effective->extra_fixed_intrinsics.push_back(index);
  Solved held = SolveOnce(views, *effective, params, false);
  held.iterations += first.iterations;
  if (held.summary.IsSolutionUsable() &&
      !CostFallsInside(held.problem.get(), params->intrinsics.data(), index, family)) {
    std::ostringstream text;
    text << ParamNames(family)[index] << " held on its bound " << params->intrinsics[index]
         << " (the optimum lies there; no standard deviation)";
    *note = text.str();
    return held;
  }
  // Not active: free again, from where the first solve ended (the bound itself may leave the
  // lens' region for some points: unified with xi = 0 projects nothing past 90 deg).
  *effective = options;
  *params = before;
  Solved again = SolveOnce(views, options, params, false);
  again.iterations += held.iterations;
  return again;
}

}  // namespace

const std::vector<std::pair<RobustLoss, const char*>>& RobustLossNames() {
  static const std::vector<std::pair<RobustLoss, const char*>> names = {
      {RobustLoss::kNone, "none"}, {RobustLoss::kHuber, "huber"}, {RobustLoss::kCauchy, "cauchy"}};
  return names;
}

bool RefineOptions::Check(std::string* why) const {
  std::string msg;
  const bool extra_in_range =
      std::all_of(extra_fixed_intrinsics.begin(), extra_fixed_intrinsics.end(),
                  [](int i) { return i >= 0 && i < PinholeSkewCamera::kNumParams; });
  if (!extra_in_range) {
    msg = "extra_fixed_intrinsics must index the raw parameter array (0..9)";
  } else {
    msg = refine_internal::SolverOptionsProblem(loss, loss_scale_px, max_iterations,
                                                known_pixel_sigma_px);
  }
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

ceres::LossFunction* refine_internal::MakeLoss(RobustLoss loss, double scale_px) {
  switch (loss) {
    case RobustLoss::kHuber:
      return new ceres::HuberLoss(scale_px);
    case RobustLoss::kCauchy:
      return new ceres::CauchyLoss(scale_px);
    case RobustLoss::kNone:
      break;
  }
  return nullptr;
}

std::string refine_internal::SolverOptionsProblem(RobustLoss loss, double loss_scale_px,
                                                  int max_iterations, double known_pixel_sigma_px) {
  if (loss != RobustLoss::kNone && loss != RobustLoss::kHuber && loss != RobustLoss::kCauchy) {
    return "loss must be none, huber or cauchy, got the value " +
           std::to_string(static_cast<int>(loss));
  }
  if (!(loss_scale_px > 0)) return "loss_scale_px must be > 0";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(known_pixel_sigma_px >= 0)) return "known_pixel_sigma_px must be >= 0";
  return "";
}

namespace {

// The start in the model's family: an initial guess of another family (e.g. a radtan zhang for
// an equidistant refinement) contributes its pinhole part only; the parameters the model leaves
// out take their neutral values (an initialisation from a richer model, e.g. OpenCV's k1, k2,
// must not stay frozen in): no distortion, beta = 1, phi = 90 degrees.
Parameters StartParameters(const CameraIntrinsics& initial, const std::vector<Rigid3>& poses,
                           const RefineOptions& options) {
  const LensFamily family = FamilyOf(options.model);
  CameraIntrinsics start = initial;
  if (start.family != family) {
    start = CameraIntrinsics();
    start.family = family;
    start.fku_px = initial.fku_px, start.fkv_px = initial.fkv_px, start.phi_deg = initial.phi_deg;
    start.u0_px = initial.u0_px, start.v0_px = initial.v0_px;
  }
  Parameters params(start, poses);
  for (int i : FixedIntrinsics(options.model, options.estimate_skew)) {
    if (options.fix_intrinsics) continue;
    params.intrinsics[i] = i == 2 ? M_PI / 2 : std::string(ParamNames(family)[i]) == "beta" ? 1 : 0;
  }
  return params;
}

// The solution's intrinsics, poses, RMS per view and overall, and sigma_hat; false when there are
// fewer residuals than free parameters.
bool FillSolution(const std::vector<View>& views, const Parameters& params,
                  const RefineOptions& effective, RefineResult* result) {
  result->intrinsics =
      CameraIntrinsics::FromParams(params.intrinsics.data(), FamilyOf(effective.model));
  for (size_t p = 0; p < params.rotations.size(); ++p)
    result->cam_from_object.push_back(params.Pose(p));
  double sum_sq = 0.0;
  for (size_t v = 0; v < views.size(); ++v) {
    const Rigid3& pose = result->cam_from_object[effective.shared_pose ? 0 : v];
    // At a usable optimum every point projects (ceres rejects steps that leave the region).
    double view_sq = 0.0;
    ViewSquaredErrorPx2(views[v], result->intrinsics, pose, &view_sq);
    sum_sq += view_sq;
    result->view_rms_px.push_back(std::sqrt(view_sq / std::max<size_t>(1, views[v].points.size())));
  }
  result->rms_reproj_px = std::sqrt(sum_sq / result->num_points);
  const int free_intrinsics =
      effective.fix_intrinsics ? 0 : kN - static_cast<int>(FixedOf(effective).size());
  const int free_params = free_intrinsics + 6 * static_cast<int>(params.rotations.size());
  const int dof = 2 * result->num_points - free_params;
  if (dof <= 0) return false;
  result->sigma_hat_px = std::sqrt(sum_sq / dof);
  return true;
}

// The covariance of the header comment and the standard deviations of the free intrinsics.
bool FillCovariance(ceres::Problem* problem, Parameters* params, const RefineOptions& effective,
                    RefineResult* result, std::string* why) {
  const double sigma =
      effective.known_pixel_sigma_px > 0 ? effective.known_pixel_sigma_px : result->sigma_hat_px;
  const std::vector<int> fixed = FixedOf(effective);
  if (effective.compute_pose_covariance && effective.shared_pose) {
    if (!JointCovariance(problem, params, fixed, sigma * sigma, &result->joint_covariance, why)) {
      return false;
    }
    // One view: z = [theta, M (delta, dt)] (batch/projection_uncertainty.h).
    Eigen::Matrix<double, ProjectionCovariance::kSize, kN + 6> to_z =
        Eigen::Matrix<double, ProjectionCovariance::kSize, kN + 6>::Zero();
    to_z.topLeftCorner<kN, kN>().setIdentity();
    to_z.bottomRightCorner<6, 6>() = PoseTangentToFrameShare(params->Pose(0), 1);
    result->projection.covariance = to_z * result->joint_covariance * to_z.transpose();
    result->projection.sigma_px = sigma;
    result->projection.num_views = 1;
  }
  if (effective.compute_pose_covariance && effective.shared_pose && effective.normal_equations) {
    // The long windows of online mode: the joint's corner (ceres::Covariance is 10x slower).
    result->covariance = result->joint_covariance.topLeftCorner<kN, kN>();
  } else if (!effective.shared_pose && AnalyticJacobians(effective)) {
    if (!PerViewIntrinsicsCovariance(problem, params, fixed, sigma * sigma, &result->covariance,
                                     &result->projection, why)) {
      return false;
    }
  } else if (!effective.shared_pose) {
    // Autodiff keeps ceres::Covariance's figure (the reference, header comment); the projection
    // covariance is an extra that does not fail the refinement.
    if (!CovarianceOfIntrinsics(problem, params, sigma * sigma, &result->covariance, why)) {
      return false;
    }
    IntrinsicsCovariance unused;
    std::string projection_why;
    if (!PerViewIntrinsicsCovariance(problem, params, fixed, sigma * sigma, &unused,
                                     &result->projection, &projection_why)) {
      result->projection = ProjectionCovariance();
    }
  } else if (!CovarianceOfIntrinsics(problem, params, sigma * sigma, &result->covariance, why)) {
    return false;
  }
  for (int i = 0; i < kN; ++i) {
    const bool is_fixed = std::find(fixed.begin(), fixed.end(), i) != fixed.end();
    if (!is_fixed) result->intrinsics_std[i] = std::sqrt(result->covariance(i, i));
  }
  return true;
}

// The view a failed solve is traced to (RefineResult::failed_view), and why, from where the solve
// started (`start`, the parameters before Solve): the first view with a point that does not
// project, else the one farthest from the start. -1 without views.
int TraceFailure(const std::vector<View>& views, const Parameters& start, LensFamily family,
                 std::string* why) {
  const CameraIntrinsics camera = CameraIntrinsics::FromParams(start.intrinsics.data(), family);
  int worst = -1;
  double worst_rms = -1;
  for (size_t v = 0; v < views.size(); ++v) {
    double sum_sq = 0;
    if (!ViewSquaredErrorPx2(views[v], camera, start.Pose(start.rotations.size() == 1 ? 0 : v),
                             &sum_sq)) {
      *why =
          "a point does not project at the start (behind the camera or outside the lens's "
          "region)";
      return static_cast<int>(v);
    }
    const double rms = std::sqrt(sum_sq / std::max<size_t>(1, views[v].points.size()));
    if (rms > worst_rms) worst_rms = rms, worst = static_cast<int>(v);
  }
  char line[96];
  std::snprintf(line, sizeof(line), "the view farthest from the start (RMS %.3g px)", worst_rms);
  *why = line;
  return worst;
}

}  // namespace

RefineResult RefineCalibration(const std::vector<View>& views, const CameraIntrinsics& initial,
                               const std::vector<Rigid3>& initial_poses,
                               const RefineOptions& options) {
  const SummaryClock clock;
  RefineResult result;
  result.intrinsics_std.fill(std::numeric_limits<double>::quiet_NaN());
  auto finish = [&](MethodStatus status, const std::string& message) {
    return clock.Finish(&result, status, message);
  };
  std::string why;
  if (!options.Check(&why)) return finish(MethodStatus::kFailed, "ceres options: " + why);
  const size_t expected_poses = options.shared_pose ? 1 : views.size();
  if (views.empty() || initial_poses.size() != expected_poses) {
    return finish(MethodStatus::kFailed, "need one initial pose per view (or one if shared)");
  }
  if (!options.view_names.empty() && options.view_names.size() != views.size()) {
    return finish(MethodStatus::kFailed, "view_names must name every view");
  }
  if (!initial.Check(&why)) return finish(MethodStatus::kFailed, "initial intrinsics: " + why);
  Parameters params = StartParameters(initial, initial_poses, options);
  const Parameters start = params;
  RefineOptions effective;  // With an active bound held.
  std::string note;
  const Solved solved = SolveRespectingBounds(views, options, &params, &effective, &note);
  result.num_points = solved.points;
  result.iterations = solved.iterations;
  if (!solved.summary.IsSolutionUsable() ||
      solved.summary.termination_type == ceres::NO_CONVERGENCE) {
    std::string traced;
    result.failed_view = TraceFailure(views, start, FamilyOf(options.model), &traced);
    if (result.failed_view >= 0) {
      traced = " Traced to " +
               (options.view_names.empty() ? "view " + std::to_string(result.failed_view)
                                           : options.view_names[result.failed_view]) +
               ": " + traced;
    }
    return finish(MethodStatus::kFailed, "ceres: " + solved.summary.message + traced);
  }
  if (!FillSolution(views, params, effective, &result)) {
    return finish(MethodStatus::kFailed, "fewer residuals than free parameters");
  }
  if (options.compute_covariance && !options.fix_intrinsics &&
      !FillCovariance(solved.problem.get(), &params, effective, &result, &why)) {
    return finish(MethodStatus::kFailed, why);
  }
  return finish(MethodStatus::kOk, note);
}

bool IntrinsicsCovarianceAt(const std::vector<View>& views, const CameraIntrinsics& intrinsics,
                            const std::vector<Rigid3>& poses, const RefineOptions& options,
                            double pixel_sigma_px, IntrinsicsCovariance* covariance,
                            std::string* why) {
  if (intrinsics.family != FamilyOf(options.model)) {
    if (why) {
      *why = std::string("no bound: the truth's lens family (") + ToString(intrinsics.family) +
             ") is not the model's (" + ToString(options.model) + ")";
    }
    return false;
  }
  Parameters params(intrinsics, poses);
  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  RefineOptions plain = options;
  plain.loss = RobustLoss::kNone;
  const int points = BuildProblem(views, plain, &params, &problem);
  if (plain.shared_pose && (plain.normal_equations || 2 * points > kTallProblemResiduals)) {
    // One pose, as FillCovariance with normal_equations, or a long trial seen from one pose (a
    // dynamic scenario: 1e6 residuals): the normal equations, equal to ~1e-10 relative, where the
    // dense SVD would take seconds.
    Eigen::MatrixXd joint;
    if (!JointCovariance(&problem, &params, FixedOf(plain), pixel_sigma_px * pixel_sigma_px, &joint,
                         why)) {
      return false;
    }
    *covariance = joint.topLeftCorner<kN, kN>();
    return true;
  }
  return CovarianceOfIntrinsics(&problem, &params, pixel_sigma_px * pixel_sigma_px, covariance,
                                why);
}

namespace refine_internal {
void SetIntrinsicsBounds(LensFamily family, double* intrinsics, ceres::Problem* problem) {
  SetLensBounds(family, intrinsics, problem);
}
}  // namespace refine_internal

Eigen::MatrixXd EstimateCovarianceOfSharedPose(const Eigen::MatrixXd& joint_covariance,
                                               const Rigid3& cam_from_parent) {
  constexpr int kJoint = PinholeSkewCamera::kNumParams + 6;
  if (joint_covariance.rows() != kJoint || joint_covariance.cols() != kJoint) return {};
  constexpr int kEstimate = 11;  // camera/estimate.h's CameraEstimate::kCovarianceSize.
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(kEstimate, kJoint);
  for (int i = 0; i < 5; ++i) j(i, i) = 1.0;  // fku, fkv, phi, u0, v0.
  const Eigen::Matrix3d& r_cam = cam_from_parent.rotation;
  const Eigen::Vector3d& t = cam_from_parent.translation;
  j.block<3, 3>(5, 10) = -2.0 * r_cam.transpose();
  j.block<3, 3>(8, 10) = -2.0 * r_cam.transpose() * Hat(t);
  j.block<3, 3>(8, 13) = -r_cam.transpose();
  return j * joint_covariance * j.transpose();
}

}  // namespace calibench
