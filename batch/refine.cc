#include "batch/refine.h"

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "batch/board_pose.h"
#include "batch/reprojection_error.h"

namespace calibench {
namespace {

constexpr int kN = PinholeSkewCamera::kNumParams;

// Parameter storage for one problem: intrinsics and poses (quaternion x, y, z, w; translation).
struct Parameters {
  IntrinsicsArray intrinsics{};
  std::vector<std::array<double, 4>> rotations;
  std::vector<std::array<double, 3>> translations;

  Parameters(const CameraIntrinsics& k, const std::vector<Rigid3>& poses) {
    intrinsics = k.Params();
    for (const Rigid3& pose : poses) {
      const Eigen::Quaterniond q(pose.rotation);
      rotations.push_back({q.x(), q.y(), q.z(), q.w()});
      translations.push_back({pose.translation.x(), pose.translation.y(), pose.translation.z()});
    }
  }
  Rigid3 Pose(size_t i) const {
    const Eigen::Quaterniond q(rotations[i][3], rotations[i][0], rotations[i][1], rotations[i][2]);
    return {q.normalized().toRotationMatrix(),
            Eigen::Vector3d(translations[i][0], translations[i][1], translations[i][2])};
  }
};

// The hand-written Jacobians cover the radtan family; other families use the ceres::Jet residual.
bool AnalyticJacobians(const RefineOptions& o) {
  return !o.autodiff && FamilyOf(o.model) == LensFamily::kRadTan;
}

ceres::LossFunction* MakeLoss(const RefineOptions& o) {
  if (o.loss == "huber") return new ceres::HuberLoss(o.loss_scale_px);
  if (o.loss == "cauchy") return new ceres::CauchyLoss(o.loss_scale_px);
  return nullptr;
}

// Builds the problem over `params`; returns the number of residual blocks (points).
int BuildProblem(const std::vector<View>& views, const RefineOptions& options, Parameters* params,
                 ceres::Problem* problem) {
  int points = 0;
  // Per-view blocks for plain least squares (same cost, less overhead); per-point blocks for a
  // robust loss (it must act on each point) and for the autodiff reference.
  const bool per_view = options.loss == "none" && AnalyticJacobians(options);
  const LensFamily family = FamilyOf(options.model);
  for (size_t v = 0; v < views.size(); ++v) {
    const size_t pose = options.shared_pose ? 0 : v;
    double* blocks[3] = {params->intrinsics.data(), params->rotations[pose].data(),
                         params->translations[pose].data()};
    points += static_cast<int>(views[v].points.size());
    if (views[v].points.empty()) continue;
    if (per_view) {
      problem->AddResidualBlock(new ViewReprojectionCostFunction(views[v].points, views[v].pixels),
                                nullptr, blocks, 3);
      continue;
    }
    for (size_t i = 0; i < views[v].points.size(); ++i) {
      ceres::CostFunction* cost =
          AnalyticJacobians(options)
              ? new ReprojectionCostFunction(views[v].pixels[i], views[v].points[i])
              : ReprojectionError::Create(views[v].pixels[i], views[v].points[i], family);
      problem->AddResidualBlock(cost, MakeLoss(options), blocks, 3);
    }
  }
  const std::vector<int> fixed = FixedIntrinsics(options.model, options.estimate_skew);
  if (options.fix_intrinsics) {
    problem->SetParameterBlockConstant(params->intrinsics.data());
  } else if (!fixed.empty()) {
    problem->SetManifold(params->intrinsics.data(), new ceres::SubsetManifold(kN, fixed));
  }
  for (auto& q : params->rotations)
    problem->SetManifold(q.data(), new ceres::EigenQuaternionManifold);
  return points;
}

bool CovarianceOfIntrinsics(ceres::Problem* problem, Parameters* params, double scale,
                            IntrinsicsCovariance* covariance, std::string* why) {
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.null_space_rank = 0;
  cov_options.min_reciprocal_condition_number = 1e-14;
  ceres::Covariance cov(cov_options);
  const double* block = params->intrinsics.data();
  std::vector<std::pair<const double*, const double*>> blocks = {{block, block}};
  if (!cov.Compute(blocks, problem)) {
    if (why) *why = "covariance: the Jacobian is rank deficient (parameters not observable)";
    return false;
  }
  Eigen::Matrix<double, kN, kN, Eigen::RowMajor> c;
  cov.GetCovarianceBlock(block, block, c.data());
  *covariance = c * scale;
  return true;
}

// The indices of the free intrinsics (not in `fixed`), increasing: SubsetManifold's tangent.
std::vector<int> FreeIntrinsics(const std::vector<int>& fixed) {
  std::vector<int> free;
  for (int i = 0; i < kN; ++i) {
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) free.push_back(i);
  }
  return free;
}

// The inverse of a symmetric information matrix J^T J, or false when its condition number passes
// 1e14 (a parameter the data do not determine).
bool InvertInformation(const Eigen::MatrixXd& information, Eigen::MatrixXd* inverse,
                       std::string* why) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(information);
  const Eigen::VectorXd& values = eig.eigenvalues();
  if (!(values[0] > 1e-14 * values[values.size() - 1])) {
    if (why) *why = "covariance: the Jacobian is rank deficient (parameters not observable)";
    return false;
  }
  *inverse =
      eig.eigenvectors() * values.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  return true;
}

// The joint covariance (RefineResult::joint_covariance) of the intrinsics and the one shared pose,
// scale (J^T J)^-1 from the Jacobian in the tangent spaces (Problem::Evaluate): 10x faster than
// ceres::Covariance's DENSE_SVD on tall problems (a window of 300 frames: 96k residuals), which
// the static mode keeps for its reported standard deviations.
bool JointCovariance(ceres::Problem* problem, Parameters* params, const std::vector<int>& fixed,
                     double scale, Eigen::MatrixXd* covariance, std::string* why) {
  double* blocks[3] = {params->intrinsics.data(), params->rotations[0].data(),
                       params->translations[0].data()};
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = {blocks[0], blocks[1], blocks[2]};
  options.apply_loss_function = true;
  // J^T J in chunks of residual blocks: a growing window's whole Jacobian in CRS form would take
  // ~20 bytes a residual (200 MB at 1e6 residuals) for a 16 x 16 result.
  std::vector<ceres::ResidualBlockId> residual_blocks;
  problem->GetResidualBlocks(&residual_blocks);
  constexpr size_t kChunk = 4096;
  const int n = kN - static_cast<int>(fixed.size()) + 6;  // Free intrinsics + 3 + 3.
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(n, n);
  ceres::CRSMatrix jacobian;
  for (size_t from = 0; from < residual_blocks.size(); from += kChunk) {
    options.residual_blocks.assign(
        residual_blocks.begin() + static_cast<long>(from),
        residual_blocks.begin() +
            static_cast<long>(std::min(residual_blocks.size(), from + kChunk)));
    if (!problem->Evaluate(options, nullptr, nullptr, nullptr, &jacobian) ||
        jacobian.num_cols != n) {
      if (why) *why = "covariance: the Jacobian could not be evaluated";
      return false;
    }
    for (int r = 0; r < jacobian.num_rows; ++r) {
      for (int a = jacobian.rows[r]; a < jacobian.rows[r + 1]; ++a) {
        for (int b = a; b < jacobian.rows[r + 1]; ++b) {
          jtj(jacobian.cols[a], jacobian.cols[b]) += jacobian.values[a] * jacobian.values[b];
        }
      }
    }
  }
  jtj = jtj.selfadjointView<Eigen::Upper>();
  Eigen::MatrixXd inverse;
  if (!InvertInformation(jtj, &inverse, why)) return false;
  // Tangent coordinates -> the 16 rows: the intrinsics' tangent holds the free parameters in
  // increasing index order (SubsetManifold).
  std::vector<int> rows = FreeIntrinsics(fixed);
  for (int i = 0; i < 6; ++i) rows.push_back(kN + i);
  *covariance = Eigen::MatrixXd::Zero(kN + 6, kN + 6);
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) (*covariance)(rows[a], rows[b]) = scale * inverse(a, b);
  }
  return true;
}

// The intrinsics' covariance with one pose per view, scale (J^T J)^-1 restricted to the intrinsics:
// the Schur complement S = A - sum_v B_v D_v^-1 B_v^T of the Jacobian in the tangent spaces
// (A: intrinsics x intrinsics, D_v: view v's 6 x 6 pose block, B_v: their coupling; a residual
// sees one pose, so D is block diagonal), inverted. The same matrix as ceres::Covariance's
// DENSE_SVD of the whole Jacobian, which costs 0.1 s on 30 views (190 parameters) against ~2 ms.
bool PerViewIntrinsicsCovariance(ceres::Problem* problem, Parameters* params,
                                 const std::vector<int>& fixed, double scale,
                                 IntrinsicsCovariance* covariance, std::string* why) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks.push_back(params->intrinsics.data());
  for (size_t v = 0; v < params->rotations.size(); ++v) {
    options.parameter_blocks.push_back(params->rotations[v].data());
    options.parameter_blocks.push_back(params->translations[v].data());
  }
  options.apply_loss_function = true;
  ceres::CRSMatrix jacobian;
  if (!problem->Evaluate(options, nullptr, nullptr, nullptr, &jacobian)) {
    if (why) *why = "covariance: the Jacobian could not be evaluated";
    return false;
  }
  const int free = kN - static_cast<int>(fixed.size());
  const int views = static_cast<int>(params->rotations.size());
  if (jacobian.num_cols != free + 6 * views) {
    if (why) *why = "covariance: unexpected Jacobian layout";
    return false;
  }
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(free, free);
  std::vector<Eigen::Matrix<double, 6, 6>> d(views, Eigen::Matrix<double, 6, 6>::Zero());
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 6>> b(views, Eigen::MatrixXd::Zero(free, 6));
  for (int r = 0; r < jacobian.num_rows; ++r) {
    for (int i = jacobian.rows[r]; i < jacobian.rows[r + 1]; ++i) {
      const int ci = jacobian.cols[i];
      for (int j = jacobian.rows[r]; j < jacobian.rows[r + 1]; ++j) {
        const int cj = jacobian.cols[j];
        const double p = jacobian.values[i] * jacobian.values[j];
        if (ci < free && cj < free) {
          a(ci, cj) += p;
        } else if (ci < free) {
          b[(cj - free) / 6](ci, (cj - free) % 6) += p;
        } else if (cj >= free && (ci - free) / 6 == (cj - free) / 6) {
          d[(ci - free) / 6]((ci - free) % 6, (cj - free) % 6) += p;
        }
      }
    }
  }
  Eigen::MatrixXd schur = a;
  for (int v = 0; v < views; ++v) {
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(d[v]);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) {
      if (why) *why = "covariance: a view's pose is not observable";
      return false;
    }
    schur -= b[v] * ldlt.solve(b[v].transpose());
  }
  Eigen::MatrixXd inverse;
  if (!InvertInformation(schur, &inverse, why)) return false;
  const std::vector<int> rows = FreeIntrinsics(fixed);  // The intrinsics' tangent, in order.
  covariance->setZero();
  for (int i = 0; i < free; ++i) {
    for (int j = 0; j < free; ++j) (*covariance)(rows[i], rows[j]) = scale * inverse(i, j);
  }
  return true;
}

// The lens families refined here. The ceres::Jet residual projects every family, but the
// omnidirectional ones need bounds (xi >= 0, alpha in [0, 1], beta > 0) and a start: not yet.
bool RefinesFamily(LensFamily family) {
  switch (family) {
    case LensFamily::kRadTan:
    case LensFamily::kEquidistant:
      return true;
    case LensFamily::kUnified:
    case LensFamily::kEucm:
    case LensFamily::kDoubleSphere:
      return false;
  }
  return false;
}

}  // namespace

bool RefineOptions::Check(std::string* why) const {
  std::string msg;
  if (!RefinesFamily(FamilyOf(model))) {
    msg = std::string("model ") + ToString(model) + ": the ceres refinement does not support the " +
          ToString(FamilyOf(model)) + " lens family yet (radtan and equidistant models only)";
  } else if (loss != "none" && loss != "huber" && loss != "cauchy") {
    msg = "loss must be none, huber or cauchy, got '" + loss + "'";
  } else if (!(loss_scale_px > 0)) {
    msg = "loss_scale_px must be > 0";
  } else if (max_iterations < 1) {
    msg = "max_iterations must be >= 1";
  } else if (!(known_pixel_sigma_px >= 0)) {
    msg = "known_pixel_sigma_px must be >= 0";
  }
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

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
  if (!initial.Check(&why)) return finish(MethodStatus::kFailed, "initial intrinsics: " + why);

  // An initial guess of another lens family (e.g. a radtan zhang for an equidistant refinement)
  // contributes its pinhole part only.
  CameraIntrinsics start = initial;
  if (start.family != FamilyOf(options.model)) {
    start = CameraIntrinsics();
    start.family = FamilyOf(options.model);
    start.fku_px = initial.fku_px, start.fkv_px = initial.fkv_px, start.phi_deg = initial.phi_deg;
    start.u0_px = initial.u0_px, start.v0_px = initial.v0_px;
  }
  Parameters params(start, initial_poses);
  // Parameters the model leaves out take their neutral values (an initialisation from a richer
  // model, e.g. OpenCV's k1, k2, must not stay frozen in): no distortion, phi = 90 degrees.
  for (int i : FixedIntrinsics(options.model, options.estimate_skew)) {
    if (!options.fix_intrinsics) params.intrinsics[i] = i == 2 ? M_PI / 2 : 0.0;
  }
  ceres::Problem problem;
  result.num_points = BuildProblem(views, options, &params, &problem);
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
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  result.iterations = static_cast<long>(summary.iterations.size());
  if (!summary.IsSolutionUsable() || summary.termination_type == ceres::NO_CONVERGENCE) {
    return finish(MethodStatus::kFailed, "ceres: " + summary.message);
  }

  result.intrinsics =
      CameraIntrinsics::FromParams(params.intrinsics.data(), FamilyOf(options.model));
  for (size_t p = 0; p < params.rotations.size(); ++p)
    result.cam_from_object.push_back(params.Pose(p));
  double sum_sq = 0.0;
  for (size_t v = 0; v < views.size(); ++v) {
    const Rigid3& pose = result.cam_from_object[options.shared_pose ? 0 : v];
    // At a usable optimum every point is in front (ceres rejects steps that leave it).
    double view_sq = 0.0;
    ViewSquaredErrorPx2(views[v], result.intrinsics, pose, &view_sq);
    sum_sq += view_sq;
    result.view_rms_px.push_back(std::sqrt(view_sq / std::max<size_t>(1, views[v].points.size())));
  }
  result.rms_reproj_px = std::sqrt(sum_sq / result.num_points);
  const int free_intrinsics =
      options.fix_intrinsics
          ? 0
          : kN - static_cast<int>(FixedIntrinsics(options.model, options.estimate_skew).size());
  const int free_params = free_intrinsics + 6 * static_cast<int>(expected_poses);
  const int dof = 2 * result.num_points - free_params;
  if (dof <= 0) return finish(MethodStatus::kFailed, "fewer residuals than free parameters");
  result.sigma_hat_px = std::sqrt(sum_sq / dof);

  if (options.compute_covariance && !options.fix_intrinsics) {
    const double sigma =
        options.known_pixel_sigma_px > 0 ? options.known_pixel_sigma_px : result.sigma_hat_px;
    const std::vector<int> fixed = FixedIntrinsics(options.model, options.estimate_skew);
    if (options.compute_pose_covariance && options.shared_pose) {
      if (!JointCovariance(&problem, &params, fixed, sigma * sigma, &result.joint_covariance,
                           &why)) {
        return finish(MethodStatus::kFailed, why);
      }
      result.covariance = result.joint_covariance.topLeftCorner<kN, kN>();
    } else if (!options.shared_pose && AnalyticJacobians(options)) {
      if (!PerViewIntrinsicsCovariance(&problem, &params, fixed, sigma * sigma, &result.covariance,
                                       &why)) {
        return finish(MethodStatus::kFailed, why);
      }
    } else if (!CovarianceOfIntrinsics(&problem, &params, sigma * sigma, &result.covariance,
                                       &why)) {
      return finish(MethodStatus::kFailed, why);
    }
    for (int i = 0; i < kN; ++i) {
      const bool is_fixed = std::find(fixed.begin(), fixed.end(), i) != fixed.end();
      if (!is_fixed) result.intrinsics_std[i] = std::sqrt(result.covariance(i, i));
    }
  }
  return finish(MethodStatus::kOk, "");
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
  plain.loss = "none";
  BuildProblem(views, plain, &params, &problem);
  return CovarianceOfIntrinsics(&problem, &params, pixel_sigma_px * pixel_sigma_px, covariance,
                                why);
}

}  // namespace calibench
