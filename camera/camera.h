// THE home of calibench's camera and lens models: the intrinsics, the projection every algorithm
// and ceres::Jet use, and the named lens models. A small value type; no I/O here.
//
// Intrinsic matrix (thesis eq. 2.5; spec "Camera model"):
//
//         [ fku   -fku*cot(phi)   u0 ]   [ a1 a2 a3 ]
//     A = [ 0      fkv/sin(phi)   v0 ] = [ 0  a4 a5 ]
//         [ 0      0              1  ]   [ 0  0  1  ]
//
// Every lens family maps point_in_cam = P = (X, Y, Z) to a point (xd, yd) of the normalised image
// plane, then [u v 1]^T = A * [xd  yd  1]^T. Distortion acts there, before A (Algers 2018, eq. 2;
// OpenCV's and Zhang's too, so A doubles as OpenCV's camera_matrix).
//
// Pixel-centre convention (the whole suite's): OpenCV's. The centre of the pixel in column i, row j
// is at (u, v) = (i, j); the image spans [-0.5, W-0.5] x [-0.5, H-0.5]. Detectors that use another
// convention (AprilTag 3 behaves as if centres were at (i+0.5, j+0.5)) convert at their boundary.
//
// radtan (LensFamily::kRadTan; OpenCV's default model), Z > 0:
//     x = X/Z, y = Y/Z;  r2 = x^2 + y^2;  d = 1 + k1*r2 + k2*r2^2 + k3*r2^3
//     xd = d*x + 2*p1*x*y + p2*(r2 + 2x^2);  yd = d*y + p1*(r2 + 2y^2) + 2*p2*x*y
//
// equidistant (LensFamily::kEquidistant; Kannala-Brandt, = OpenCV's cv::fisheye and Kalibr's
// `equidistant`): with r = sqrt(x^2 + y^2) and theta = atan(r) (the angle from the axis),
//     theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
//     xd = (theta_d / r) x,  yd = (theta_d / r) y      (xd = x, yd = y at r = 0)
// Only points with Z > 0 project (theta < 90 deg), as in OpenCV and Kalibr.
//
// The three omnidirectional families see past 90 deg (Z <= 0). Each projects only inside its valid
// region, where the image radius still grows with the angle from the axis: past its edge the
// image folds over (or the denominator changes sign). Their inverses lift (xd, yd) to a unit ray.
//
// unified (LensFamily::kUnified; Mei & Rives 2007 = Kalibr's `omni` + `radtan`, cv::omnidir): P
// onto the unit sphere, seen by a pinhole xi behind its centre, then radtan (k3 = 0) on that image:
//     rho = |P|;  (mx, my) = (X, Y) / (Z + xi*rho);  (xd, yd) = radtan(mx, my)
//   Valid: Z > -w*rho with w = xi (xi <= 1: the denominator stays > 0) or w = 1/xi (xi > 1: the
//   sphere's rim, r2 = mx^2 + my^2 = 1/(xi^2 - 1)). Field of view 2 acos(-w): xi = 0 (radtan
//   with k3 = 0) 180 deg, xi = 0.5 240 deg, xi = 1 all but the backward axis, xi = 1.6 257 deg.
//   Inverse (Mei's lift, after radtan^-1): f = (xi + sqrt(1 + (1 - xi^2) r2)) / (1 + r2),
//   ray = (f mx, f my, f - xi).
//
// eucm (LensFamily::kEucm; Khomenko et al. 2016, basalt's and Kalibr's `eucm`): unified on an
// ellipsoid (beta), xi = alpha / (1 - alpha), the image scaled by 1 / (1 - alpha):
//     d = sqrt(beta (X^2 + Y^2) + Z^2);  (xd, yd) = (X, Y) / (alpha d + (1 - alpha) Z)
//   Valid: Z > -w d, w = alpha/(1 - alpha) for alpha <= 1/2, (1 - alpha)/alpha above (basalt's).
//   alpha = 0 is the pinhole. Inverse, r2 = xd^2 + yd^2 (alpha > 1/2: r2 < 1/(beta (2 alpha - 1))):
//     mz = (1 - beta alpha^2 r2) / (alpha sqrt(1 - (2 alpha - 1) beta r2) + 1 - alpha)
//     ray = (xd, yd, mz) / |(xd, yd, mz)|
//
// double-sphere (LensFamily::kDoubleSphere; Usenko, Demmel, Cremers 3DV 2018, basalt's `ds`): P
// onto the unit sphere, moved xi along the axis onto a second sphere, seen as eucm (beta = 1):
//     d1 = |P|;  k = xi d1 + Z;  d2 = sqrt(X^2 + Y^2 + k^2);
//     (xd, yd) = (X, Y) / (alpha d2 + (1 - alpha) k)
//   Valid: Z > -w2 d1, with w1 = alpha/(1 - alpha) (alpha <= 1/2) or (1 - alpha)/alpha, and
//     w2 = xi (1 - w1^2) + w1 sqrt(1 - xi^2 (1 - w1^2))   (-1 < xi <= 1),   w2 = 1/xi   (xi > 1),
//   where the moved direction reaches the eucm edge (cos = -w1), or the first sphere's rim. The
//   paper's and basalt's w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1) lies inside it for xi in
//   [0, 1], refusing up to 45 deg of valid field (alpha = 0, i.e. unified: xi = 1/2 stops at 116.6
//   deg instead of 120, xi = 1 at 135 instead of 180), and past it for xi > 1 (a fold).
//   Inverse: mz as eucm with beta = 1, f = (mz xi + sqrt(mz^2 + (1 - xi^2) r2)) / (mz^2 + r2),
//   ray = (f xd, f yd, f mz - xi) (xi > 1: the square root's argument and f must be positive).
//   xi may be negative (real fisheyes fit xi ~ -0.2: TUM VI's -0.18, basalt's and ours), down to
//   xi > -1, where the second centre would leave the first sphere (the moved direction then no
//   longer turns monotonically with the angle).
//
// Parameter order of the raw array used by Project() (kNumParams = 10): five pinhole slots
// [fku_px, fkv_px, phi_rad, u0_px, v0_px], then five lens slots whose meaning is the family's
// (0: unused, kept at 0):
//     radtan (PinholeSkewCamera):          [..., k1, k2, p1, p2, k3]
//     equidistant (PinholeEquiCamera):     [..., k1, k2, k3, k4, 0]
//     unified (UnifiedCamera):             [..., xi, k1, k2, p1, p2]
//     eucm (EucmCamera):                   [..., alpha, beta, 0, 0, 0]
//     double-sphere (DoubleSphereCamera):  [..., xi, alpha, 0, 0, 0]
// phi is in radians in the raw array (the Jet-friendly form) and in degrees in CameraIntrinsics.
// The camera types are declared, with each family's facts, in camera/lens_families.h;
// VisitLensFamily picks one for a batch of points, ProjectLens<T>(family, ...) for one point.
//
// Lens models (LensModel, the table LensModels() in camera.cc) name the family and which of those
// parameters an estimator frees; the others stay at their neutral value (0, beta = 1, or phi = 90
// deg unless skew is estimated). Names are what configs and the CLI use: pinhole, pinhole-k2 (k1,
// k2), pinhole-radtan4 (k1, k2, p1, p2), pinhole-radtan5 (k1, k2, p1, p2, k3), pinhole-equi
// (equidistant k1..k4), unified (xi, k1, k2, p1, p2), eucm (alpha, beta), double-sphere (xi,
// alpha).
//
// Adding a lens model (the recipe; docs/camera-models.md, "Adding a lens model", has it in full):
//   1. Within an existing family (as pinhole-k2 in radtan): an enumerator of LensModel and its row
//      in LensModels() (name, free slots); the table test of tests/camera/camera_test.cc takes it.
//      `calibrate --model` and the methods' `model:` option read the table. 2 files + 1 test.
//   2. A new family: declared once, in the list of camera/lens_families.h (its enumerator, its
//      camera type with Project<T> and the kInfo row: name, lens slots, ranges, sight past 90
//      deg, ray space, camera-file names, example lens; its case in VisitLensFamily, its row in
//      kLensFamilies). Everything else that needs a fact of a family reads the row. The
//      behaviour still written per family is in exhaustive switches (-Wswitch-enum warns at each
//      until it has the case): camera.cc (the inverse in RayOfDistorted/UndistortNormalized, the
//      DistortionIsMonotone* tests; its model's row in LensModels()), this file (its LensModel,
//      its math above, a field for a new parameter), batch/projection_jacobian.cc (the lens step
//      and its Jacobians), batch/wide_init.cc (its start), io/camera_io_opencv.cc (how
//      the OpenCV file holds it); bench/config/scenario_fields.cc documents a new field; and
//      docs/camera-models.md's tables. At most 8 files, tests and other docs included:
//      tests/camera/lens_family_list_test.cc and tests/io/lens_family_camera_files_test.cc
//      loop over the list. Measured before the list on double-sphere: 16 source files, 11 test
//      files, 1 config, 5 doc pages.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "camera/lens_families.h"

namespace calibench {

// "radtan", "equidistant", "unified", "eucm", "double-sphere".
const char* ToString(LensFamily family);

struct CameraIntrinsics {
  double fku_px = 800.0;  // f * ku: focal length in horizontal pixels.
  double fkv_px = 800.0;  // f * kv: focal length in vertical pixels.
  double phi_deg = 90.0;  // Angle between the sensor axes; 90 = no skew. Valid in (0, 180).
  double u0_px = 320.0;   // Principal point, pixel-centre convention above.
  double v0_px = 240.0;
  double k1 = 0.0;  // Radial (radtan and unified: of r^2, r^4, r^6; equidistant: theta^2..8).
  double k2 = 0.0;
  double p1 = 0.0;  // Tangential distortion (radtan and unified).
  double p2 = 0.0;
  double k3 = 0.0;                          // Sixth-order radial term (equidistant: theta^6).
  double k4 = 0.0;                          // Equidistant only: theta^8.
  LensFamily family = LensFamily::kRadTan;  // How the lens fields are read (header comment).
  // The omnidirectional families' fields (neutral for the other families):
  double xi = 0.0;     // Unified (>= 0), double-sphere (> -1): the (first) sphere's offset.
  double alpha = 0.0;  // Eucm, double-sphere: the weight of the last projection, in [0, 1].
  double beta = 1.0;   // Eucm: the ellipsoid's shape (1 = sphere), > 0.

  // Positive finite focal lengths, phi in (0, 180) degrees, finite principal point and lens
  // fields; no field the family lacks away from its neutral value (e.g. k4 for radtan, xi for
  // eucm, beta != 1 but for eucm); xi >= 0 (unified) or > -1 (double sphere), alpha in [0, 1],
  // beta > 0 where the family has them.
  bool Check(std::string* why) const;
  // Not a plain pinhole: any distortion term, or any family but radtan (equidistant with k = 0 is
  // still r = f theta; eucm with alpha = 0 is a pinhole, reported distorted all the same).
  bool IsDistorted() const {
    return family != LensFamily::kRadTan || k1 != 0 || k2 != 0 || k3 != 0 || k4 != 0 || p1 != 0 ||
           p2 != 0;
  }
  // For a ray in front at r2 = (X^2 + Y^2) / Z^2: the lens maps the angle from the axis to the
  // image radius one-to-one there (radtan: d r_d / d r > 0 at r = |(x, y)|; equidistant: at
  // theta; the omnidirectional families: inside the valid region, and unified's radtan does not
  // fold at the sphere image's radius). Beyond the first r where it fails, the image folds over.
  bool DistortionIsMonotoneAt(double r2) const;
  // The same for any point, past 90 deg too: false outside the family's valid region (radtan and
  // equidistant: Z <= 0), else DistortionIsMonotoneAt's test at the point's direction.
  bool DistortionIsMonotoneAlong(const Eigen::Vector3d& point_in_cam) const;

  // The 3x3 matrix A above (distortion is not part of it).
  Eigen::Matrix3d Matrix() const;
  // Inverse of Matrix() for an upper-triangular A with a33 = 1 (a1, a4 > 0); distortion is zero.
  static CameraIntrinsics FromMatrix(const Eigen::Matrix3d& a);

  std::array<double, 10> Params() const;  // The family's layout (parameter order above).
  static CameraIntrinsics FromParams(const double* params, LensFamily family = LensFamily::kRadTan);
};

// Names of the raw slots 0..9 for `family` ("-" for an unused slot), e.g. for reports.
const std::array<const char*, 10>& ParamNames(LensFamily family);
// The field of `k` a lens slot's name stands for ("k1", "xi", "beta", ...; ParamNames); nullptr for
// "-" and for names that are no lens field.
const double* LensField(const CameraIntrinsics& k, const std::string& name);
double* LensField(CameraIntrinsics* k, const std::string& name);

// One value per entry of the raw parameter array (e.g. standard deviations; phi in radians).
using IntrinsicsArray = std::array<double, PinholeSkewCamera::kNumParams>;

// Convenience for double: projects with `intrinsics`; false outside the valid region (radtan and
// equidistant: Z <= 0).
bool ProjectPoint(const CameraIntrinsics& intrinsics, const Eigen::Vector3d& point_in_cam,
                  Eigen::Vector2d* pixel);

// The unit ray P / |P| of the points that project to `pixel`, for every family (the inverse of
// ProjectPoint up to depth; Z <= 0 for an omnidirectional lens past 90 deg). radtan: fixed-point
// iteration to 1e-12, damped Newton where that stops contracting (unified's radtan too, out to
// the sphere's edge); equidistant: Newton on theta; the others closed form
// (header comment). False where no ray projects there (past the valid region or a fold-over) or
// an iteration does not converge; never a ray outside the region.
bool UnprojectToRay(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel,
                    Eigen::Vector3d* ray_in_cam);
// UnprojectToRay from the normalised image point `distorted` = A^-1 (u, v, 1), before A: for
// callers that unproject many pixels with A^-1 at hand (UnprojectToRay inverts A at each call).
bool RayOfDistorted(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& distorted,
                    Eigen::Vector3d* ray_in_cam);

// Undistorts normalised coordinates: the (x, y) = (X/Z, Y/Z) whose projection before A is
// `distorted` (the inverse of the family's lens above, as UnprojectToRay). Returns false where
// UnprojectToRay does and where the ray is not in front (Z <= 0).
bool UndistortNormalized(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& distorted,
                         Eigen::Vector2d* undistorted);

// The inverse of ProjectPoint up to depth: the undistorted normalised coordinates (X/Z, Y/Z) of
// the ray through `pixel` (A^-1, then UndistortNormalized). False where UndistortNormalized is.
bool UnprojectPixel(const CameraIntrinsics& intrinsics, const Eigen::Vector2d& pixel,
                    Eigen::Vector2d* normalized);

bool operator==(const CameraIntrinsics& a, const CameraIntrinsics& b);
inline bool operator!=(const CameraIntrinsics& a, const CameraIntrinsics& b) { return !(a == b); }

// The named lens models (see the header comment and the recipe above).
enum class LensModel {
  kPinhole,
  kPinholeK2,
  kPinholeRadTan4,
  kPinholeRadTan5,
  kPinholeEqui,
  kUnified,
  kEucm,
  kDoubleSphere
};

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
// The model of `family` that frees every one of its lens parameters (radtan: pinhole-radtan5).
LensModel FullModelOf(LensFamily family);
bool ParseLensModel(const std::string& name, LensModel* model);
std::vector<std::string> LensModelNames();
// Indices into PinholeSkewCamera's parameter array that stay fixed: phi (index 2) unless the skew
// is estimated, and the lens slots the model does not free.
std::vector<int> FixedIntrinsics(LensModel model, bool estimate_skew);

}  // namespace calibench
