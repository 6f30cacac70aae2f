#include "batch/extrinsic_from_views.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>

namespace calibench {

Rigid3 AveragePoses(const std::vector<Rigid3>& poses) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (const Rigid3& p : poses) {
    sum += p.rotation;
    position += p.translation;
  }
  return {ProjectToSO3(sum), position / static_cast<double>(poses.size())};
}

namespace {

// HandEyeTsai's input checks: one body pose per board pose, at least 3, finite, and relative
// rotations about at least two non-parallel axes (Tsai's equations need them).
bool CheckHandEyeInput(const std::vector<Rigid3>& parent_from_points,
                       const std::vector<Rigid3>& cam_from_target, std::string* why) {
  const size_t n = cam_from_target.size();
  if (parent_from_points.size() != n) {
    if (why) {
      *why = "hand-eye needs one body pose per board pose: got " +
             std::to_string(parent_from_points.size()) + " body poses and " + std::to_string(n) +
             " board poses";
    }
    return false;
  }
  if (n < 3) {
    if (why) *why = "hand-eye needs at least 3 views of board 0, got " + std::to_string(n);
    return false;
  }
  for (size_t v = 0; v < n; ++v) {
    const Rigid3& p = parent_from_points[v];
    const Rigid3& c = cam_from_target[v];
    if (!(p.rotation.allFinite() && p.translation.allFinite() && c.rotation.allFinite() &&
          c.translation.allFinite())) {
      if (why) *why = "hand-eye: the poses of view " + std::to_string(v) + " are not finite";
      return false;
    }
  }
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  for (size_t i = 1; i < n; ++i) {
    const Eigen::AngleAxisd rel(parent_from_points[i].rotation *
                                parent_from_points[i - 1].rotation.transpose());
    if (rel.angle() > 1e-3) axes += rel.axis() * rel.axis().transpose();
  }
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(axes).eigenvalues();
  if (!(spread[1] > 1e-3 * spread[2])) {
    if (why) {
      *why =
          "hand-eye is degenerate: the body rotates about a single axis (or not at all); "
          "it needs rotations about two non-parallel axes";
    }
    return false;
  }
  return true;
}

// Tsai's rotation step on the pairs A X = X B: q_A q_X - q_X q_B = 0, 4 rows a pair, in
// q = (w, x, y, z), solved by SVD. False when the null space has more than one dimension (to a
// numerical rank of 1e-9): the rotation is then free.
bool HandEyeRotation(const std::vector<Rigid3>& a, const std::vector<Rigid3>& b,
                     Eigen::Matrix3d* r_x) {
  Eigen::MatrixXd m(4 * a.size(), 4);
  for (size_t k = 0; k < a.size(); ++k) {
    Eigen::Quaterniond qa(a[k].rotation), qb(b[k].rotation);
    if (qa.w() < 0) qa.coeffs() = -qa.coeffs();
    if (qb.w() < 0) qb.coeffs() = -qb.coeffs();
    const Eigen::Vector3d d = qa.vec() - qb.vec();
    m.block<4, 4>(4 * k, 0) << qa.w() - qb.w(), -d.transpose(), d,
        (qa.w() - qb.w()) * Eigen::Matrix3d::Identity() + Hat(qa.vec() + qb.vec());
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeFullV);
  const Eigen::Vector4d sv = svd.singularValues();
  if (!(sv[2] > 1e-9 * sv[0])) return false;
  const Eigen::Vector4d q = svd.matrixV().col(3);
  *r_x = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  return true;
}

}  // namespace

bool HandEyeTsai(const std::vector<Rigid3>& parent_from_points,
                 const std::vector<Rigid3>& cam_from_target, Rigid3* parent_from_cam,
                 std::string* why) {
  if (!CheckHandEyeInput(parent_from_points, cam_from_target, why)) return false;
  const size_t n = cam_from_target.size();
  // The pairs (i < j): A = P_j P_i^-1, B = C_j C_i^-1, A X = X B.
  std::vector<Rigid3> a, b;
  const double min_half_cos = std::cos(0.5 * kHandEyeMaxPairTurnDeg * M_PI / 180.0);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const Rigid3 a_ij = parent_from_points[j] * parent_from_points[i].Inverse();
      const Rigid3 b_ij = cam_from_target[j] * cam_from_target[i].Inverse();
      // |w| = cos(theta / 2) of the pair's turn: below min_half_cos, noise would pair q_A with
      // -q_B.
      if (std::abs(Eigen::Quaterniond(a_ij.rotation).w()) < min_half_cos) continue;
      a.push_back(a_ij);
      b.push_back(b_ij);
    }
  }
  Eigen::Matrix3d r_x;
  if (a.empty() || !HandEyeRotation(a, b, &r_x)) {
    if (why) {
      *why = "hand-eye is degenerate: the relative rotations (of at most " +
             std::to_string(kHandEyeMaxPairTurnDeg) + " deg) do not fix the camera's rotation";
    }
    return false;
  }
  // Translation (Tsai's step): (R_A - I) t_X = R_X t_B - t_A.
  Eigen::MatrixXd lhs(3 * a.size(), 3);
  Eigen::VectorXd rhs(3 * a.size());
  for (size_t k = 0; k < a.size(); ++k) {
    lhs.block<3, 3>(3 * k, 0) = a[k].rotation - Eigen::Matrix3d::Identity();
    rhs.segment<3>(3 * k) = r_x * b[k].translation - a[k].translation;
  }
  const Eigen::Vector3d t_x = lhs.colPivHouseholderQr().solve(rhs);
  *parent_from_cam = {r_x, t_x};
  if (!(r_x.allFinite() && t_x.allFinite())) {
    if (why) *why = "hand-eye gave a non-finite pose";
    return false;
  }
  return true;
}

}  // namespace calibench
