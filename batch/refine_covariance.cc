// The covariance computations of RefineCalibration (batch/refine.h, header comment).
#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>

#include "batch/refine_internal.h"

namespace calibench {
namespace refine_internal {
namespace {

constexpr int kN = PinholeSkewCamera::kNumParams;

// The indices of the free intrinsics (not in `fixed`), increasing: SubsetManifold's tangent.
std::vector<int> FreeIntrinsics(const std::vector<int>& fixed) {
  std::vector<int> free;
  for (int i = 0; i < kN; ++i) {
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) free.push_back(i);
  }
  return free;
}

// The inverse of a symmetric information matrix J^T J, or false when its condition number passes
// 1e14 (a parameter the data do not determine). The test is made on the matrix scaled to a unit
// diagonal (D^-1/2 S D^-1/2, D = diag S), so that the parameters' units do not count: a focal
// length in pixels beside xi or k4 spans 1e10 in J^T J on their own (seen: unified and double
// sphere fits refused at a well-determined optimum).
bool InvertInformation(const Eigen::MatrixXd& information, Eigen::MatrixXd* inverse,
                       std::string* why) {
  const Eigen::VectorXd diagonal = information.diagonal();
  if (!(diagonal.minCoeff() > 0)) {
    if (why) *why = "covariance: the Jacobian is rank deficient (a parameter has no effect)";
    return false;
  }
  const Eigen::VectorXd scale = diagonal.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = scale.asDiagonal() * information * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
  const Eigen::VectorXd& values = eig.eigenvalues();
  if (!(values[0] > 1e-14 * values[values.size() - 1])) {
    if (why) *why = "covariance: the Jacobian is rank deficient (parameters not observable)";
    return false;
  }
  *inverse =
      scale.asDiagonal() *
      (eig.eigenvectors() * values.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose()) *
      scale.asDiagonal();
  return true;
}

}  // namespace

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
  // J^T J in chunks of residual blocks of ~kChunkResiduals residuals (a block is a point or a
  // whole view): a growing window's whole Jacobian in CRS form would take ~20 bytes a residual
  // (200 MB at 1e6 residuals) for a 16 x 16 result, and a chunk that fits in the cache is
  // reused without page faults.
  std::vector<ceres::ResidualBlockId> residual_blocks;
  problem->GetResidualBlocks(&residual_blocks);
  constexpr int kChunkResiduals = 8192;
  const int n = kN - static_cast<int>(fixed.size()) + 6;  // Free intrinsics + 3 + 3.
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(n, n);
  ceres::CRSMatrix jacobian;
  for (size_t from = 0, to = 0; from < residual_blocks.size(); from = to) {
    int residuals = 0;
    for (to = from; to < residual_blocks.size() && (to == from || residuals < kChunkResiduals);
         ++to) {
      residuals += problem->GetCostFunctionForResidualBlock(residual_blocks[to])->num_residuals();
    }
    options.residual_blocks.assign(residual_blocks.begin() + static_cast<long>(from),
                                   residual_blocks.begin() + static_cast<long>(to));
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
//
// With `projection`: also Cov(z) of batch/projection_uncertainty.h, z = [theta, y], y = sum_v M_v
// b_v (M_v = PoseTangentToFrameShare, b_v view v's tangent). With Sigma = (J^T J)^-1 in blocks,
// Sigma_theta,theta = S^-1, Sigma_theta,b_v = -S^-1 B_v D_v^-1 and
// Sigma_b_v,b_w = D_v^-1 delta_vw + D_v^-1 B_v^T S^-1 B_w D_w^-1:
//     Cov(theta, y) = -S^-1 W^T,  Cov(y) = sum_v M_v D_v^-1 M_v^T + W S^-1 W^T,
//     W = sum_v M_v D_v^-1 B_v^T  (6 x free intrinsics).
bool PerViewIntrinsicsCovariance(ceres::Problem* problem, Parameters* params,
                                 const std::vector<int>& fixed, double scale,
                                 IntrinsicsCovariance* covariance, ProjectionCovariance* projection,
                                 std::string* why) {
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
  Eigen::Matrix<double, 6, Eigen::Dynamic> w = Eigen::MatrixXd::Zero(6, free);
  Eigen::Matrix<double, 6, 6> frame_share = Eigen::Matrix<double, 6, 6>::Zero();
  for (int v = 0; v < views; ++v) {
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(d[v]);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) {
      if (why) *why = "covariance: a view's pose is not observable";
      return false;
    }
    const Eigen::Matrix<double, 6, Eigen::Dynamic> d_inv_bt = ldlt.solve(b[v].transpose());
    schur -= b[v] * d_inv_bt;
    if (projection) {
      const Eigen::Matrix<double, 6, 6> m = PoseTangentToFrameShare(params->Pose(v), views);
      w += m * d_inv_bt;
      frame_share += m * ldlt.solve(m.transpose());
    }
  }
  Eigen::MatrixXd inverse;
  if (!InvertInformation(schur, &inverse, why)) return false;
  const std::vector<int> rows = FreeIntrinsics(fixed);  // The intrinsics' tangent, in order.
  covariance->setZero();
  for (int i = 0; i < free; ++i) {
    for (int j = 0; j < free; ++j) (*covariance)(rows[i], rows[j]) = scale * inverse(i, j);
  }
  if (projection) {
    const Eigen::MatrixXd theta_y = -inverse * w.transpose();  // free x 6.
    const Eigen::Matrix<double, 6, 6> y_y = frame_share + w * inverse * w.transpose();
    ProjectionCovariance::Matrix& z = projection->covariance;
    z.setZero();
    z.topLeftCorner<kN, kN>() = *covariance;
    for (int i = 0; i < free; ++i) {
      for (int k = 0; k < 6; ++k) {
        z(rows[i], kN + k) = z(kN + k, rows[i]) = scale * theta_y(i, k);
      }
    }
    z.bottomRightCorner<6, 6>() = scale * 0.5 * (y_y + y_y.transpose());
    projection->sigma_px = std::sqrt(scale);
    projection->num_views = views;
  }
  return true;
}

bool InvertInformationMatrix(const Eigen::MatrixXd& information, Eigen::MatrixXd* inverse,
                             std::string* why) {
  return InvertInformation(information, inverse, why);
}

}  // namespace refine_internal
}  // namespace calibench
