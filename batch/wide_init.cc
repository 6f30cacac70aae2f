#include "batch/wide_init.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "batch/board_pose.h"
#include "batch/refine.h"

namespace calibench {
namespace {

// Equidistant projects in front only: its cone fit and its views stop this far from the axis.
constexpr double kEquidistantMaxDeg = 89.5;
// Rays sampled for the cone fit (uniform in the angle).
constexpr int kConeSamples = 200;

// One scored candidate of the scan: the unified shape xi and the focal length on the axis.
struct Candidate {
  double xi = 0, focal_px = 0;
  int posed = 0;
  double rms_px = std::numeric_limits<double>::infinity();
};

// More views posed, then the smaller RMS.
bool Better(const Candidate& a, const Candidate& b) {
  return a.posed != b.posed ? a.posed > b.posed : a.rms_px < b.rms_px;
}

CameraIntrinsics UnifiedProfile(double xi, double focal_px, const WideInitOptions& o) {
  CameraIntrinsics k;
  k.family = LensFamily::kUnified;
  k.xi = xi;
  k.fku_px = k.fkv_px = focal_px * (1.0 + xi);  // gamma.
  k.u0_px = 0.5 * (o.image_width - 1);
  k.v0_px = 0.5 * (o.image_height - 1);
  return k;
}

// Poses every view of `views` (indices `which`) through `camera`; the posed ones (all points
// projecting) go to *used / *poses with their squared error. Returns the summed squared error.
struct Posed {
  std::vector<int> used;
  std::vector<Rigid3> poses;
  double sum_sq_px2 = 0;
  long points = 0;
  double RmsPx() const {
    return points > 0 ? std::sqrt(sum_sq_px2 / static_cast<double>(points))
                      : std::numeric_limits<double>::infinity();
  }
};
Posed PoseViews(const std::vector<View>& views, const std::vector<int>& which,
                const CameraIntrinsics& camera, const BoardPoseOptions& pnp = {}) {
  Posed out;
  for (int v : which) {
    Rigid3 pose;
    double sq = 0;
    if (!BoardPoseFromIntrinsics(views[v], camera, &pose, nullptr, pnp) ||
        !ViewSquaredErrorPx2(views[v], camera, pose, &sq)) {
      continue;
    }
    out.used.push_back(v);
    out.poses.push_back(pose);
    out.sum_sq_px2 += sq;
    out.points += static_cast<long>(views[v].points.size());
  }
  return out;
}

Candidate Score(const std::vector<View>& views, const std::vector<int>& which, double xi,
                double focal_px, const WideInitOptions& o) {
  BoardPoseOptions ippe_only;  // A candidate's score needs no LM (BoardPoseOptions).
  ippe_only.refine = false;
  const Posed posed = PoseViews(views, which, UnifiedProfile(xi, focal_px, o), ippe_only);
  Candidate c;
  c.xi = xi;
  c.focal_px = focal_px;
  c.posed = static_cast<int>(posed.used.size());
  c.rms_px = posed.RmsPx();
  return c;
}

// Golden-section search of log f in [lo, hi] for the shape of `best`; returns the better.
Candidate RefineFocal(const std::vector<View>& views, const std::vector<int>& which,
                      const Candidate& best, double lo, double hi, const WideInitOptions& o) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = std::log(lo), b = std::log(hi);
  Candidate result = best;
  Candidate c1 = Score(views, which, best.xi, std::exp(b - g * (b - a)), o);
  Candidate c2 = Score(views, which, best.xi, std::exp(a + g * (b - a)), o);
  for (int it = 0; it < 12; ++it) {
    if (Better(c1, c2)) {
      b = std::log(c2.focal_px);
      c2 = c1;
      c1 = Score(views, which, best.xi, std::exp(b - g * (b - a)), o);
    } else {
      a = std::log(c1.focal_px);
      c1 = c2;
      c2 = Score(views, which, best.xi, std::exp(a + g * (b - a)), o);
    }
  }
  for (const Candidate& c : {c1, c2}) {
    if (Better(c, result)) result = c;
  }
  return result;
}

// At most `max` indices of 0..n-1, evenly spaced.
std::vector<int> EvenlySpaced(int n, int max) {
  std::vector<int> which;
  const int count = std::min(n, max);
  which.reserve(std::max(count, 0));
  for (int i = 0; i < count; ++i)
    which.push_back(static_cast<int>(i * static_cast<long>(n) / count));
  return which;
}

// Step 1: the best (shape, focal length) over the grid, then refined in f.
Candidate ScanProfiles(const std::vector<View>& views, const WideInitOptions& o) {
  const std::vector<int> which = EvenlySpaced(static_cast<int>(views.size()), o.max_scan_views);
  const double half_side = 0.5 * std::min(o.image_width, o.image_height);
  const double lo = o.min_focal_per_half_side * half_side;
  const double ratio =
      std::pow(o.max_focal_per_half_side / o.min_focal_per_half_side, 1.0 / (o.focal_steps - 1));
  Candidate best;
  for (double xi : o.shape_xis) {
    for (int s = 0; s < o.focal_steps; ++s) {
      const Candidate c = Score(views, which, xi, lo * std::pow(ratio, s), o);
      if (Better(c, best)) best = c;
    }
  }
  if (best.posed == 0) return best;
  return RefineFocal(views, which, best, best.focal_px / ratio, best.focal_px * ratio, o);
}

// Step 2: ceres on the unified profile (fku, fkv, centre, xi; no distortion).
bool PolishProfile(const std::vector<View>& views, Posed* posed, CameraIntrinsics* profile) {
  std::vector<View> used;
  for (int v : posed->used) used.push_back(views[v]);
  RefineOptions polish;
  polish.model = LensModel::kUnified;
  polish.estimate_skew = false;
  polish.extra_fixed_intrinsics = {6, 7, 8, 9};  // k1, k2, p1, p2.
  polish.compute_covariance = false;
  polish.max_iterations = 50;
  const RefineResult r = RefineCalibration(used, *profile, posed->poses, polish);
  if (!r.IsUsable()) return false;
  *profile = r.intrinsics;
  posed->poses = r.cam_from_object;
  posed->sum_sq_px2 = r.rms_reproj_px * r.rms_reproj_px * r.num_points;
  posed->points = r.num_points;
  return true;
}

// The largest angle from the axis of the used views' rays through `camera` [rad].
double MaxRayAngle(const std::vector<View>& views, const std::vector<int>& used,
                   const CameraIntrinsics& camera) {
  double widest = 0;
  for (int v : used) {
    for (const Eigen::Vector2d& pixel : views[v].pixels) {
      Eigen::Vector3d ray;
      if (UnprojectToRay(camera, pixel, &ray)) widest = std::max(widest, std::acos(ray.z()));
    }
  }
  return widest;
}

// Step 3 for equidistant: the cone fit of the header comment.
CameraIntrinsics EquidistantFromProfile(const CameraIntrinsics& u, double max_angle_rad) {
  Eigen::Matrix<double, kConeSamples, 5> a;
  Eigen::Matrix<double, kConeSamples, 1> b;
  for (int j = 0; j < kConeSamples; ++j) {
    const double theta = max_angle_rad * (j + 1) / kConeSamples, t2 = theta * theta;
    b[j] = std::sin(theta) / (std::cos(theta) + u.xi);  // The profile before A.
    double power = theta;
    for (int i = 0; i < 5; ++i, power *= t2) a(j, i) = power;
  }
  const Eigen::Matrix<double, 5, 1> x = a.colPivHouseholderQr().solve(b);
  CameraIntrinsics k = u;
  k.family = LensFamily::kEquidistant;
  k.xi = 0;
  k.fku_px = u.fku_px * x[0];
  k.fkv_px = u.fkv_px * x[0];
  k.k1 = x[1] / x[0], k.k2 = x[2] / x[0], k.k3 = x[3] / x[0], k.k4 = x[4] / x[0];
  return k;
}

// Step 3 for the double sphere with a given xi: alpha and f by linear least squares over the cone
// of rays (header comment). False when no positive focal length fits.
bool DoubleSphereFromProfile(const CameraIntrinsics& u, double max_angle_rad, double xi,
                             CameraIntrinsics* ds) {
  Eigen::Matrix<double, kConeSamples, 2> a;
  Eigen::Matrix<double, kConeSamples, 1> b;
  for (int j = 0; j < kConeSamples; ++j) {
    const double theta = max_angle_rad * (j + 1) / kConeSamples;
    const double c = std::cos(theta), k = xi + c;
    const double d2 = std::sqrt(1 + 2 * xi * c + xi * xi);
    a(j, 0) = k, a(j, 1) = d2 - k;
    b[j] = c + u.xi;  // sin(theta) / m(theta) of the unified profile.
  }
  const Eigen::Vector2d x = a.colPivHouseholderQr().solve(b);
  if (!(x[0] > 0)) return false;
  *ds = u;
  ds->family = LensFamily::kDoubleSphere;
  ds->xi = xi;
  ds->alpha = std::clamp(x[1] / x[0], 0.0, 1.0);
  ds->fku_px = u.fku_px / x[0];
  ds->fkv_px = u.fkv_px / x[0];
  return true;
}

// Ceres on the requested model from `camera` and the poses of *posed (no covariance); false when it
// fails.
bool RefineStart(const std::vector<View>& views, LensModel model, CameraIntrinsics* camera,
                 Posed* posed) {
  std::vector<View> used;
  for (int v : posed->used) used.push_back(views[v]);
  RefineOptions refine;
  refine.model = model;
  refine.estimate_skew = false;
  refine.compute_covariance = false;
  const RefineResult r = RefineCalibration(used, *camera, posed->poses, refine);
  if (!r.IsUsable()) return false;
  *camera = r.intrinsics;
  posed->poses = r.cam_from_object;
  posed->sum_sq_px2 = r.rms_reproj_px * r.rms_reproj_px * r.num_points;
  posed->points = r.num_points;
  return true;
}

// The double sphere's start: its profiles with xi = +kDoubleSphereXi and -kDoubleSphereXi fold
// onto each other near xi = 0 (the singularity of the header comment), and ceres stays on the
// side it starts from (seen: a lens with xi -0.2 fitted at xi +0.3, 90 std off, at the same RMS
// to 1e-4 px). Both are refined; the lower RMS wins.
constexpr double kDoubleSphereXi = 0.2;
bool DoubleSphereStart(const std::vector<View>& views, const Posed& profile_posed,
                       const CameraIntrinsics& profile, double max_angle_rad,
                       CameraIntrinsics* camera, Posed* posed) {
  bool found = false;
  for (double xi : {-kDoubleSphereXi, kDoubleSphereXi}) {
    CameraIntrinsics ds;
    if (!DoubleSphereFromProfile(profile, max_angle_rad, xi, &ds)) continue;
    Posed p = PoseViews(views, profile_posed.used, ds);
    if (p.used.size() < 2 || !RefineStart(views, LensModel::kDoubleSphere, &ds, &p)) continue;
    if (!found || p.RmsPx() < posed->RmsPx()) {
      *camera = ds;
      *posed = p;
      found = true;
    }
  }
  return found;
}

// Step 3: the requested family from the polished profile.
CameraIntrinsics FromProfile(LensFamily family, const CameraIntrinsics& u, double max_angle_rad) {
  CameraIntrinsics k = u;
  const double alpha = u.xi / (1.0 + u.xi);
  switch (family) {
    case LensFamily::kEquidistant:
      return EquidistantFromProfile(u, max_angle_rad);
    case LensFamily::kEucm:
      k.family = family;
      k.xi = 0;
      k.alpha = alpha;
      k.beta = 1;
      k.fku_px = u.fku_px * (1.0 - alpha);  // gamma / (1 + xi).
      k.fkv_px = u.fkv_px * (1.0 - alpha);
      return k;
    case LensFamily::kRadTan:
    case LensFamily::kUnified:
    case LensFamily::kDoubleSphere:  // DoubleSphereStart.
      break;
  }
  return k;
}

std::string Describe(const Candidate& c, int scanned) {
  char text[200];
  std::snprintf(text, sizeof(text),
                "RMS %.3g px at f %.1f px, unified shape xi %.2f, %d of %d views", c.rms_px,
                c.focal_px, c.xi, c.posed, scanned);
  return text;
}

// The message of a start: the profile, the scan, the family, the views.
std::string Summarise(const WideInitResult& r, size_t views, double widest_rad, double cone_rad) {
  char text[400];
  const LensFamily family = r.intrinsics.family;
  std::snprintf(text, sizeof(text),
                "wide start: unified profile xi %.3f, f %.1f px (scan RMS %.3g px over %d views, "
                "polished %.3g px) -> %s, RMS %.3g px, %zu of %zu views",
                r.profile.xi, r.profile.fku_px / (1 + r.profile.xi), r.scan_rms_px,
                r.scan_views_posed, r.profile_rms_px, ToString(family), r.rms_reproj_px,
                r.used_views.size(), views);
  std::string message = text;
  if (family == LensFamily::kEquidistant && widest_rad >= cone_rad) {
    std::snprintf(text, sizeof(text),
                  "; rays reach %.1f deg from the axis, equidistant projects below 90: views past "
                  "%.1f deg left out",
                  widest_rad * 180 / M_PI, kEquidistantMaxDeg);
    message += text;
  }
  return message;
}

}  // namespace

bool WideInitServes(LensFamily family) { return family != LensFamily::kRadTan; }

bool WideInitOptions::Check(std::string* why) const {
  std::string msg;
  if (!WideInitServes(FamilyOf(model))) {
    msg = std::string("the wide start serves pinhole-equi, unified, eucm and double-sphere, not ") +
          ToString(model) + " (radtan models start from zhang)";
  } else if (image_width <= 0 || image_height <= 0) {
    msg = "image size must be positive";
  } else if (shape_xis.empty() ||
             !std::all_of(shape_xis.begin(), shape_xis.end(), [](double x) { return x >= 0; })) {
    msg = "shape_xis must hold at least one xi >= 0";
  } else if (!(min_focal_per_half_side > 0 && max_focal_per_half_side > min_focal_per_half_side)) {
    msg = "focal range must satisfy 0 < min < max";
  } else if (focal_steps < 2 || max_scan_views < 2) {
    msg = "focal_steps and max_scan_views must be >= 2";
  } else if (!(max_start_rms_px > 0)) {
    msg = "max_start_rms_px must be > 0";
  }
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

WideInitResult InitializeWideCamera(const std::vector<View>& views, const WideInitOptions& o) {
  const SummaryClock clock;
  WideInitResult result;
  auto fail = [&](const std::string& message) {
    return clock.Finish(&result, MethodStatus::kFailed, "wide start: " + message);
  };
  std::string why;
  if (!o.Check(&why)) return fail(why);
  for (size_t v = 0; v < views.size(); ++v) {
    for (const Eigen::Vector3d& p : views[v].points) {
      if (std::abs(p.z()) > 1e-9) return fail("view " + std::to_string(v) + " is not planar");
    }
  }
  if (views.size() < 2) return fail("needs at least 2 views of the board");
  // 1. The scan.
  const Candidate best = ScanProfiles(views, o);
  result.scan_views = std::min(static_cast<int>(views.size()), o.max_scan_views);
  result.scan_xi = best.xi, result.scan_focal_px = best.focal_px, result.scan_rms_px = best.rms_px;
  result.scan_views_posed = best.posed;
  if (best.posed < 2) {
    return fail("no focal length poses two views (best: " + Describe(best, result.scan_views) +
                ")");
  }
  // 2. The polish, on every view posed through the scan's camera.
  std::vector<int> all(views.size());
  for (size_t v = 0; v < views.size(); ++v) all[v] = static_cast<int>(v);
  CameraIntrinsics profile = UnifiedProfile(best.xi, best.focal_px, o);
  Posed posed = PoseViews(views, all, profile);
  if (posed.used.size() < 2 || !PolishProfile(views, &posed, &profile)) {
    return fail("the unified profile did not refine (scan: " + Describe(best, result.scan_views) +
                ")");
  }
  result.profile = profile;
  result.profile_rms_px = posed.RmsPx();
  // 3, 4. The family and its poses.
  const LensFamily family = FamilyOf(o.model);
  const double widest = MaxRayAngle(views, posed.used, profile);
  const double cone = std::min(widest, kEquidistantMaxDeg * M_PI / 180.0);
  Posed start;
  if (family == LensFamily::kDoubleSphere) {
    if (!DoubleSphereStart(views, posed, profile, cone, &result.intrinsics, &start)) {
      char line[160];
      std::snprintf(line, sizeof(line),
                    "no double sphere fits the unified profile (xi %.3f, f %.1f px, RMS %.3g px "
                    "over %zu views; best scan: ",
                    profile.xi, profile.fku_px / (1 + profile.xi), result.profile_rms_px,
                    posed.used.size());
      return fail(line + Describe(best, result.scan_views) + ")");
    }
  } else {
    result.intrinsics = FromProfile(family, profile, cone);
    // Unified and eucm hold the profile exactly: the polished poses stay.
    const bool exact = family == LensFamily::kUnified || family == LensFamily::kEucm;
    start = exact ? posed : PoseViews(views, posed.used, result.intrinsics);
  }
  result.used_views = start.used;
  result.cam_from_board = start.poses;
  result.rms_reproj_px = start.RmsPx();
  const std::string message = Summarise(result, views.size(), widest, cone);
  if (start.used.size() < 2 || !(result.rms_reproj_px <= o.max_start_rms_px)) {
    return fail(message.substr(std::string("wide start: ").size()) + ": the start's RMS exceeds " +
                std::to_string(o.max_start_rms_px) +
                " px or fewer than 2 views (best scan: " + Describe(best, result.scan_views) + ")");
  }
  return clock.Finish(&result, MethodStatus::kOk, message);
}

}  // namespace calibench
