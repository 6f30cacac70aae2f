// THE home of calibench's camera and lens models: the intrinsics, the projection every algorithm
// and ceres::Jet use, and the named lens models. A small value type; no I/O here.
//
// Intrinsic matrix (thesis eq. 2.5; spec "Camera model"):
//
//         [ fku   -fku*cot(phi)   u0 ]   [ a1 a2 a3 ]
//     A = [ 0      fkv/sin(phi)   v0 ] = [ 0  a4 a5 ]
//         [ 0      0              1  ]   [ 0  0  1  ]
//
// Projection of point_in_cam = (X, Y, Z), Z > 0:
//     x = X/Z, y = Y/Z;  r2 = x^2 + y^2;  d = 1 + k1*r2 + k2*r2^2 + k3*r2^3
//     xd = d*x + 2*p1*x*y + p2*(r2 + 2x^2);  yd = d*y + p1*(r2 + 2y^2) + 2*p2*x*y
//     [u v 1]^T = A * [xd  yd  1]^T
// Distortion acts in normalised coordinates, after the perspective division and before A (seed
// 001's model; OpenCV's and Zhang's too, so A doubles as OpenCV's camera_matrix).
//
// Pixel-centre convention (the whole suite's): OpenCV's. The centre of the pixel in column i, row j
// is at (u, v) = (i, j); the image spans [-0.5, W-0.5] x [-0.5, H-0.5]. Detectors that use another
// convention (AprilTag 3 behaves as if centres were at (i+0.5, j+0.5)) convert at their boundary.
//
// Fisheye lens family (LensFamily::kEquidistant; Kannala-Brandt, = OpenCV's cv::fisheye and
// Kalibr's `equidistant`): with r = sqrt(x^2 + y^2) and theta = atan(r) (the angle from the axis),
//     theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
//     xd = (theta_d / r) x,  yd = (theta_d / r) y      (xd = x, yd = y at r = 0)
//     [u v 1]^T = A * [xd  yd  1]^T
// Only points with Z > 0 project (theta < 90 deg), as in OpenCV and Kalibr.
//
// Parameter order of the raw array used by Project() (kNumParams = 10): five pinhole slots, then
// five distortion slots whose meaning is the lens family's:
//     radtan (PinholeSkewCamera):      [fku_px, fkv_px, phi_rad, u0_px, v0_px, k1, k2, p1, p2, k3]
//     equidistant (PinholeEquiCamera): [fku_px, fkv_px, phi_rad, u0_px, v0_px, k1, k2, k3, k4, 0]
// phi is in radians in the raw array (the Jet-friendly form) and in degrees in CameraIntrinsics.
// ProjectLens<T>(family, ...) dispatches between the two.
//
// Lens models (LensModel, the table LensModels() in camera.cc) name the family and which of those
// parameters an estimator frees; the others stay at their neutral value (0, or phi = 90 deg unless
// skew is estimated). Names are what configs and the CLI use: pinhole, pinhole-k2 (k1, k2),
// pinhole-radtan4 (k1, k2, p1, p2), pinhole-radtan5 (k1, k2, p1, p2, k3), pinhole-equi
// (equidistant k1..k4).
//
// Adding a lens model (the recipe; every place that knows lens models is listed here):
//   1. core/camera.h, camera.cc: an enumerator of LensModel and its row in LensModels() (name,
//      free distortion parameters). Config files, the resolved YAML, `calibrate --model` and
//      camera.yaml take the name from the table: nothing else to edit there.
//   2. If the model is not a subset of an existing family (a new projection, as equidistant was),
//      add a LensFamily, its slot layout in Params()/FromParams() and ParamNames(), a camera
//      type with its Project<T> and a case in ProjectLens<T>, its inverse in UndistortNormalized()
//      and its fold-over test in DistortionIsMonotoneAt() (camera.cc; the renderer casts rays
//      through them). The ceres refinement then uses the Jet residual for it (refine.cc picks
//      autodiff for any family without analytic Jacobians in batch/reprojection_error.cc).
//   3. batch/zhang.cc: map it to OpenCV (calibrateCamera flags, or cv::fisheye for equidistant;
//      the switch fails to compile with -Wswitch until it does), or refuse it with a message.
//   4. The camera file formats (bench/config/camera_io.cc): how opencv / kalibr / mrcal spell it,
//   or
//      a refusal with the reason.
//   5. tests/core/camera_test.cc: add it to the lens-model table test; the Jet and round-trip
//      tests there take every family.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace calibench {

// How the five distortion slots are read (see the parameter order above).
enum class LensFamily { kRadTan, kEquidistant };
const char* ToString(LensFamily family);

struct CameraIntrinsics {
  double fku_px = 800.0;  // f * ku: focal length in horizontal pixels.
  double fkv_px = 800.0;  // f * kv: focal length in vertical pixels.
  double phi_deg = 90.0;  // Angle between the sensor axes; 90 = no skew. Valid in (0, 180).
  double u0_px = 320.0;   // Principal point, pixel-centre convention above.
  double v0_px = 240.0;
  double k1 = 0.0;  // Radial distortion (radtan: of r^2, r^4, r^6; equidistant: of theta^2..8).
  double k2 = 0.0;
  double p1 = 0.0;  // Tangential distortion (radtan only; 0 for equidistant).
  double p2 = 0.0;
  double k3 = 0.0;                          // Sixth-order radial term (equidistant: theta^6).
  double k4 = 0.0;                          // Equidistant only: theta^8 (0 for radtan).
  LensFamily family = LensFamily::kRadTan;  // How k1..k4, p1, p2 are read (header comment).

  // Positive finite focal lengths, phi in (0, 180) degrees, finite principal point and
  // distortion; no coefficient the family lacks (p1, p2 for equidistant; k4 for radtan).
  bool Check(std::string* why) const;
  // Not a plain pinhole: any distortion term, or any fisheye (equidistant with k = 0 is still
  // r = f theta).
  bool IsDistorted() const {
    return family != LensFamily::kRadTan || k1 != 0 || k2 != 0 || k3 != 0 || k4 != 0 || p1 != 0 ||
           p2 != 0;
  }
  // The distortion maps radius (radtan: r = |(x, y)|; equidistant: theta) one-to-one at r2 = r^2:
  // d r_d / d r > 0. Beyond the first r where it fails, the image folds over.
  bool DistortionIsMonotoneAt(double r2) const;

  // The 3x3 matrix A above (distortion is not part of it).
  Eigen::Matrix3d Matrix() const;
  // Inverse of Matrix() for an upper-triangular A with a33 = 1 (a1, a4 > 0); distortion is zero.
  static CameraIntrinsics FromMatrix(const Eigen::Matrix3d& a);

  std::array<double, 10> Params() const;  // The family's layout (parameter order above).
  static CameraIntrinsics FromParams(const double* params, LensFamily family = LensFamily::kRadTan);
};

// Names of the raw slots 0..9 for `family` ("-" for an unused slot), e.g. for reports.
const std::array<const char*, 10>& ParamNames(LensFamily family);

// pixel = A (xd, yd, 1): the pinhole slots 0..4 (fku, fkv, phi_rad, u0, v0) of every family.
template <typename T>
void ApplyIntrinsicMatrix(const T* params, const T& xd, const T& yd, T* pixel) {
  using std::cos;
  using std::sin;
  const T sin_phi = sin(params[2]);
  const T cos_phi = cos(params[2]);
  pixel[0] = params[0] * (xd - yd * cos_phi / sin_phi) + params[3];
  pixel[1] = params[1] * yd / sin_phi + params[4];
}

struct PinholeSkewCamera {
  static constexpr int kNumParams = 10;
  static constexpr const char* kName = "pinhole-skew-radtan5";

  // Projects point_in_cam (3 values) to pixel (2 values). Returns false, leaving pixel untouched,
  // when the point is not strictly in front of the camera (Z <= 0). Never throws.
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    if (!(point_in_cam[2] > T(0))) return false;
    const T x = point_in_cam[0] / point_in_cam[2];
    const T y = point_in_cam[1] / point_in_cam[2];
    const T r2 = x * x + y * y;
    const T d = T(1) + r2 * (params[5] + r2 * (params[6] + r2 * params[9]));
    const T xy = x * y;
    const T xd = d * x + T(2) * params[7] * xy + params[8] * (r2 + T(2) * x * x);
    const T yd = d * y + params[7] * (r2 + T(2) * y * y) + T(2) * params[8] * xy;
    ApplyIntrinsicMatrix(params, xd, yd, pixel);
    return true;
  }
};

// The equidistant (Kannala-Brandt) fisheye; same pinhole slots, distortion slots k1..k4.
struct PinholeEquiCamera {
  static constexpr int kNumParams = 10;
  static constexpr const char* kName = "pinhole-skew-equidistant";

  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::atan;
    using std::sqrt;
    if (!(point_in_cam[2] > T(0))) return false;
    const T x = point_in_cam[0] / point_in_cam[2];
    const T y = point_in_cam[1] / point_in_cam[2];
    const T r2 = x * x + y * y;
    // theta_d / r; at r -> 0 it tends to 1 (and its derivatives in x, y to 0): sqrt would give the
    // Jet an infinite derivative there.
    T scale(1);
    if (r2 > T(1e-24)) {
      const T r = sqrt(r2);
      const T theta = atan(r);
      const T t2 = theta * theta;
      const T theta_d =
          theta * (T(1) + t2 * (params[5] + t2 * (params[6] + t2 * (params[7] + t2 * params[8]))));
      scale = theta_d / r;
    }
    ApplyIntrinsicMatrix(params, scale * x, scale * y, pixel);
    return true;
  }
};

// Project<T> of `family`'s camera type.
template <typename T>
bool ProjectLens(LensFamily family, const T* params, const T* point_in_cam, T* pixel) {
  switch (family) {
    case LensFamily::kRadTan:
      return PinholeSkewCamera::Project(params, point_in_cam, pixel);
    case LensFamily::kEquidistant:
      return PinholeEquiCamera::Project(params, point_in_cam, pixel);
  }
  return false;
}

// One value per entry of the raw parameter array (e.g. standard deviations; phi in radians).
using IntrinsicsArray = std::array<double, PinholeSkewCamera::kNumParams>;

// Convenience for double: projects with `intrinsics`, returns false behind the camera.
bool ProjectPoint(const CameraIntrinsics& intrinsics, const Eigen::Vector3d& point_in_cam,
                  Eigen::Vector2d* pixel);

// Undistorts normalised coordinates: the (x, y) = (X/Z, Y/Z) whose projection before A is
// `distorted` (the inverse of the family's distortion above). radtan: fixed-point iteration to
// 1e-12; equidistant: Newton on theta. Returns false if it does not converge or leaves the model's
// valid region (theta >= 90 deg, or past a fold-over).
bool UndistortNormalized(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& distorted,
                         Eigen::Vector2d* undistorted);

// The inverse of ProjectPoint up to depth: the undistorted normalised coordinates (X/Z, Y/Z) of
// the ray through `pixel` (A^-1, then UndistortNormalized). False where UndistortNormalized is.
bool UnprojectPixel(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel,
                    Eigen::Vector2d* normalized);

bool operator==(const CameraIntrinsics& a, const CameraIntrinsics& b);
inline bool operator!=(const CameraIntrinsics& a, const CameraIntrinsics& b) { return !(a == b); }

// The named lens models (see the header comment and the recipe above).
enum class LensModel { kPinhole, kPinholeK2, kPinholeRadTan4, kPinholeRadTan5, kPinholeEqui };

struct LensModelInfo {
  LensModel model;
  const char* name;  // As configs and the CLI spell it.
  LensFamily family;
  std::vector<int> free_distortion;  // Indices into the parameter array (5..9) it estimates.
};
// Every lens model, in a fixed order (the order of LensModelNames()).
const std::vector<LensModelInfo>& LensModels();
const char* ToString(LensModel model);
LensFamily FamilyOf(LensModel model);
bool ParseLensModel(const std::string& name, LensModel* model);
std::vector<std::string> LensModelNames();
// Indices into PinholeSkewCamera's parameter array that stay fixed: phi (index 2) unless the skew
// is estimated, and the distortion terms the model lacks.
std::vector<int> FixedIntrinsics(LensModel model, bool estimate_skew);

}  // namespace calibench
