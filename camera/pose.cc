#include "camera/pose.h"

#include <Eigen/SVD>
#include <cmath>
#include <sstream>

namespace calibench {

bool operator==(const Rigid3& a, const Rigid3& b) {
  return a.rotation == b.rotation && a.translation == b.translation;
}
namespace {
constexpr double kRadToDeg = 180.0 / M_PI;
}  // namespace

Eigen::Matrix<double, 3, 4> Rigid3::Matrix3x4() const {
  Eigen::Matrix<double, 3, 4> rt;
  rt << rotation, translation;
  return rt;
}

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d h;
  h << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return h;
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  const Eigen::Matrix3d k = Hat(w);
  if (angle < 1e-8) {
    // Taylor series to third order: error O(angle^4) < 1e-32.
    return Eigen::Matrix3d::Identity() + k + 0.5 * k * k;
  }
  const double a = std::sin(angle) / angle;
  const double b = (1.0 - std::cos(angle)) / (angle * angle);
  return Eigen::Matrix3d::Identity() + a * k + b * k * k;
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d& r) {
  // Eigen's quaternion from a rotation matrix is stable at every angle (Shepperd's method); the
  // angle from atan2 of the vector and scalar parts is accurate near 0 and near pi alike.
  Eigen::Quaterniond q(r);
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double sin_half = q.vec().norm();
  if (sin_half < 1e-12) return 2.0 * q.vec();  // angle ~ 2 sin(angle / 2): error O(angle^3).
  const double angle = 2.0 * std::atan2(sin_half, q.w());
  return q.vec() * (angle / sin_half);
}

bool CheckRotation(const Eigen::Matrix3d& r, double tol, bool allow_improper, std::string* why) {
  std::ostringstream msg;
  if (!r.allFinite()) {
    msg << "rotation has non-finite entries";
  } else {
    const double defect = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    const double det = r.determinant();
    if (defect > tol) {
      msg << "rotation is not orthonormal: max |R^T R - I| = " << defect << " > " << tol;
    } else if (det < 0 && !allow_improper) {
      msg << "rotation is improper (det = " << det
          << ", a reflection); fix the matrix, or set allow_improper_rotation: true to reproduce "
             "a source that printed it";
    }
  }
  if (msg.str().empty()) return true;
  if (why) *why = msg.str();
  return false;
}

double OrthogonalityDefect(const Eigen::Matrix3d& r) {
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
}

Eigen::Matrix3d ProjectToSO3(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

double RotationAngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const Eigen::Matrix3d rel = ProjectToSO3(a * b.transpose());
  // atan2 of (|axis part|, cos part) is accurate for small and large angles alike.
  const Eigen::Vector3d axis(rel(2, 1) - rel(1, 2), rel(0, 2) - rel(2, 0), rel(1, 0) - rel(0, 1));
  return std::atan2(0.5 * axis.norm(), 0.5 * (rel.trace() - 1.0)) * kRadToDeg;
}

Eigen::Vector3d RollPitchYawDeg(const Eigen::Matrix3d& r) {
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return Eigen::Vector3d(roll, pitch, yaw) * kRadToDeg;
}

Eigen::Matrix3d FromRollPitchYawDeg(const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d rpy = rpy_deg / kRadToDeg;
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace calibench
