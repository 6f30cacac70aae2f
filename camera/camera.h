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
// ProjectLens<T>(family, ...) dispatches between them.
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
//   2. A new family (as unified, eucm, double-sphere): in camera.h/.cc its LensFamily and
//      ToString(), slots in Params()/FromParams()/ParamNames() (Check() refuses the coefficients
//      a family lacks from ParamNames()), field ranges in Check(), a camera type with Project<T>
//      and its case in ProjectLens<T>, its inverse in UnprojectToRay() (UndistortNormalized and
//      UnprojectPixel follow), its meaning of DistortionIsMonotoneAt() and
//      DistortionIsMonotoneAlong(); a model (step 1).
//   3. Each place outside camera/ that knows the families takes the new one or refuses it with a
//      message. -Wswitch warns (the tree has no -Werror) at every switch over LensFamily or
//      LensModel without the new case; the places marked + are if-chains, tables or lists, which
//      do not warn:
//      sim/board_shader.h RaySpaceOf (the renderer's ray table: plane z = 1, or stereographic
//      past 90 deg); batch/projection_jacobian.cc (the lens step and its Jacobians);
//      batch/refine.cc SetLensBounds; batch/zhang.cc CalibrateZhang (OpenCV's flags or a
//      refusal); batch/wide_init.cc (the family's start: FromProfile or its own);
//      bench/config/camera_io_opencv.cc (+ distortion_model names) and camera_io_kalibr.cc
//      (+ KalibrModels); bench/config/scenario_fields.cc (+ lens_family names, the xi/alpha/beta
//      docs; then scripts/update_config_reference.sh);
//      for rays past 90 deg: methods/method.cc RefuseWideLens (+) and bench/config/scenario.cc
//      RenderingOptions (+);
//      bench/app/model_select.cc AutoCandidates (+), the same list in --model's help
//      (bench/app/main.cc), methods/zhang.cc's `model` option doc;
//      bench/micro/calibrate_benchmark.cc (+ kModels and the argument ranges).
//   4. The tests that go over every family (11 files), an example in configs/examples/, and the
//      docs: camera-models.md, cli.md, outputs.md, methods.md, configuration.md (regenerated).
//   Measured on double-sphere: 16 source files, 11 test files, 1 config, 5 doc pages.
//   No case is needed in code that goes through UnprojectToRay and ProjectPoint only (the
//   photometric fit's tangent plane, the frame detector's square painting), in
//   bench/app/image_points.cc (curved tag edges for every family but radtan) or in the mrcal
//   writer (it refuses every family but radtan by name).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace calibench {

// How the five lens slots are read (see the parameter order above).
enum class LensFamily { kRadTan, kEquidistant, kUnified, kEucm, kDoubleSphere };
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

// OpenCV's radial-tangential distortion of normalised (x, y) (header comment): radtan and unified.
// xd, yd must not alias x, y.
template <typename T>
void ApplyRadTan(const T& k1, const T& k2, const T& p1, const T& p2, const T& k3, const T& x,
                 const T& y, T* xd, T* yd) {
  const T r2 = x * x + y * y;
  const T d = T(1) + r2 * (k1 + r2 * (k2 + r2 * k3));
  const T xy = x * y;
  *xd = d * x + T(2) * p1 * xy + p2 * (r2 + T(2) * x * x);
  *yd = d * y + p1 * (r2 + T(2) * y * y) + T(2) * p2 * xy;
}

// d(xd, yd) / d(x, y) of ApplyRadTan: the inverse's Newton step (camera.cc) and the refinement's
// analytic Jacobians (batch/projection_jacobian.cc).
inline Eigen::Matrix2d RadTanJacobian(double k1, double k2, double p1, double p2, double k3,
                                      double x, double y) {
  const double r2 = x * x + y * y;
  const double d = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double dd_dr2 = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2);
  const double cross = 2.0 * x * y * dd_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
  Eigen::Matrix2d j;
  j << d + 2.0 * x * x * dd_dr2 + 2.0 * p1 * y + 6.0 * p2 * x, cross,  //
      cross, d + 2.0 * y * y * dd_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
  return j;
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
    T xd, yd;
    ApplyRadTan(params[5], params[6], params[7], params[8], params[9], x, y, &xd, &yd);
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

// The omnidirectional cameras below return false, leaving pixel untouched, for a point outside
// their valid region (header comment; this includes parameters outside their ranges and the
// origin). Every square root taken for a valid point is of a positive number (finite Jets).

// w of the eucm edge Z > -w d for weight alpha (also the double sphere's w1); alpha in [0, 1].
template <typename T>
T EucmEdgeWeight(const T& alpha) {
  return alpha > T(0.5) ? (T(1) - alpha) / alpha : alpha / (T(1) - alpha);
}

// Mei's unified model with radtan (k1, k2, p1, p2) on the sphere's image.
struct UnifiedCamera {
  static constexpr int kNumParams = 10;
  static constexpr const char* kName = "pinhole-skew-unified";

  template <typename T>
  static bool InRegion(const T& xi, const T& z, const T& rho) {
    const T w = xi > T(1) ? T(1) / xi : xi;
    return z > -w * rho;
  }
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::sqrt;
    const T &x = point_in_cam[0], &y = point_in_cam[1], &z = point_in_cam[2];
    const T rho = sqrt(x * x + y * y + z * z);
    if (!InRegion(params[5], z, rho)) return false;
    const T den = z + params[5] * rho;
    T xd, yd;
    ApplyRadTan(params[6], params[7], params[8], params[9], T(0), x / den, y / den, &xd, &yd);
    ApplyIntrinsicMatrix(params, xd, yd, pixel);
    return true;
  }
};

// The extended unified model (alpha, beta).
struct EucmCamera {
  static constexpr int kNumParams = 10;
  static constexpr const char* kName = "pinhole-skew-eucm";

  template <typename T>
  static bool InRegion(const T& alpha, const T& beta, const T& z, const T& d) {
    if (!(alpha >= T(0) && alpha <= T(1) && beta > T(0))) return false;
    return z > -EucmEdgeWeight(alpha) * d;
  }
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::sqrt;
    const T &x = point_in_cam[0], &y = point_in_cam[1], &z = point_in_cam[2];
    const T &alpha = params[5], &beta = params[6];
    const T d = sqrt(beta * (x * x + y * y) + z * z);
    if (!InRegion(alpha, beta, z, d)) return false;
    const T den = alpha * d + (T(1) - alpha) * z;
    ApplyIntrinsicMatrix(params, x / den, y / den, pixel);
    return true;
  }
};

// The double sphere model (xi, alpha).
struct DoubleSphereCamera {
  static constexpr int kNumParams = 10;
  static constexpr const char* kName = "pinhole-skew-double-sphere";

  template <typename T>
  static bool InRegion(const T& xi, const T& alpha, const T& z, const T& d1) {
    using std::sqrt;
    if (!(alpha >= T(0) && alpha <= T(1))) return false;
    const T w1 = EucmEdgeWeight(alpha), u = T(1) - w1 * w1;
    const T w2 = xi > T(1) ? T(1) / xi : xi * u + w1 * sqrt(T(1) - xi * xi * u);
    return z > -w2 * d1;
  }
  template <typename T>
  static bool Project(const T* params, const T* point_in_cam, T* pixel) {
    using std::sqrt;
    const T &x = point_in_cam[0], &y = point_in_cam[1], &z = point_in_cam[2];
    const T &xi = params[5], &alpha = params[6];
    const T r2 = x * x + y * y;
    const T d1 = sqrt(r2 + z * z);
    if (!InRegion(xi, alpha, z, d1)) return false;
    const T k = xi * d1 + z;
    const T den = alpha * sqrt(r2 + k * k) + (T(1) - alpha) * k;
    ApplyIntrinsicMatrix(params, x / den, y / den, pixel);
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
    case LensFamily::kUnified:
      return UnifiedCamera::Project(params, point_in_cam, pixel);
    case LensFamily::kEucm:
      return EucmCamera::Project(params, point_in_cam, pixel);
    case LensFamily::kDoubleSphere:
      return DoubleSphereCamera::Project(params, point_in_cam, pixel);
  }
  return false;
}

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
