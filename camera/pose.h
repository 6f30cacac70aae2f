// Rigid poses and rotations: THE one place that says how calibench stores a pose.
//
// Convention (as COLMAP's Rigid3d): a pose named `b_from_a` maps a point expressed in frame A to
// the same point expressed in frame B:
//
//     point_in_b = b_from_a.rotation * point_in_a + b_from_a.translation
//
// Composition reads right to left: c_from_a = c_from_b * b_from_a. The inverse of b_from_a is
// a_from_b. `rotation` is a proper rotation (SO(3), det = +1) unless a caller explicitly opted in
// to an improper one (the thesis's printed matrices for cameras 2 and 3 have det = -1).
//
// Frames used across calibench: W world, B moving body, C camera. The thesis writes the camera
// extrinsic as (R_C, x_C) = the camera's orientation and position in its parent frame P (W for a
// fixed camera, B for a moving camera), i.e. parent_from_cam = {R_C, x_C}; the projection uses
// cam_from_parent = {R = R_C^T, t = -R_C^T x_C}.
//
// Euler angles: yaw-pitch-roll about z, y, x (R = Rz(yaw) * Ry(pitch) * Rx(roll)), in degrees.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace calibench {

struct Rigid3 {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return rotation * point + translation;
  }
  Rigid3 operator*(const Rigid3& a_from_x) const {
    return {rotation * a_from_x.rotation, rotation * a_from_x.translation + translation};
  }
  // Valid for proper and improper orthogonal rotations alike (uses the transpose).
  Rigid3 Inverse() const { return {rotation.transpose(), -(rotation.transpose() * translation)}; }
  // The 3x4 matrix [R | t].
  Eigen::Matrix<double, 3, 4> Matrix3x4() const;
};

bool operator==(const Rigid3& a, const Rigid3& b);
inline bool operator!=(const Rigid3& a, const Rigid3& b) { return !(a == b); }

// Hat operator: Hat(w) * x == w.cross(x).
Eigen::Matrix3d Hat(const Eigen::Vector3d& w);
// Exponential map of so(3) (Rodrigues), exact for any |w| including 0.
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& w);
// Its inverse: the rotation vector (axis times angle, radians, |w| <= pi) of a proper rotation,
// ExpSO3(LogSO3(r)) = r; accurate near 0 and near pi.
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& r);

// True when `r` is orthogonal to `tol` (max |R^T R - I| entry) and det(r) = +1 (or -1 when
// `allow_improper`). On false, *why (if given) says which test failed and by how much.
bool CheckRotation(const Eigen::Matrix3d& r, double tol, bool allow_improper, std::string* why);

// ||R^T R - I||_F: how far an estimated matrix is from orthonormal.
double OrthogonalityDefect(const Eigen::Matrix3d& r);

// Nearest proper rotation in the Frobenius norm (SVD, with the sign fixed so det = +1).
Eigen::Matrix3d ProjectToSO3(const Eigen::Matrix3d& m);

// Geodesic angle (degrees) of a_from_b = a * b^T after projecting it onto SO(3). For two improper
// matrices a * b^T is proper, so this also compares matrices of the same handedness.
double RotationAngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

// Yaw-pitch-roll (degrees, see the header comment) of a proper rotation: [roll, pitch, yaw].
Eigen::Vector3d RollPitchYawDeg(const Eigen::Matrix3d& r);
Eigen::Matrix3d FromRollPitchYawDeg(const Eigen::Vector3d& roll_pitch_yaw_deg);

}  // namespace calibench
