#include "detect/corner_bias.h"

#include <chrono>
#include <cmath>
#include <memory>

#include "core/pose.h"
#include "core/random.h"
#include "core/render.h"
#include "core/tag_family.h"
#include "core/target.h"
#include "detect/apriltag_detector.h"
#include "detect/corner_refinement.h"

namespace calibench {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Matrix3d RotX(double rad) {
  return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d RotZ(double rad) {
  return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Per-corner errors of the draws of one view, then of the views of a case.
struct CaseSums {
  // Eigen's default constructor does not zero: every sum starts from Zero() (CaseSums()).
  std::array<Eigen::Vector2d, 4> bias_sum, bias_sq_sum;  // Over views, of b_vk.
  std::array<Eigen::Vector2d, 4> radial_sum;             // Over views, of r_vk.
  double noise_sq_sum = 0;   // Over views, draws and corners, of |e - b_v|^2.
  double noise_dof = 0;      // Sum over views of (draws - 1): b_v uses one draw's worth.
  double inverse_draws = 0;  // Sum over views of 1 / draws (the noise left in each b_v).
  int views = 0, draws = 0;
  CaseSums() {
    for (int k = 0; k < 4; ++k)
      bias_sum[k] = bias_sq_sum[k] = radial_sum[k] = Eigen::Vector2d::Zero();
  }
  // One view: its draws' errors and its corners' outward directions.
  void AddView(const std::vector<std::array<Eigen::Vector2d, 4>>& errors,
               const std::array<Eigen::Vector2d, 4>& radial) {
    if (errors.empty()) return;
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      for (const auto& e : errors) b += e[k] / static_cast<double>(errors.size());
      for (const auto& e : errors) noise_sq_sum += (e[k] - b).squaredNorm();
      bias_sum[k] += b;
      bias_sq_sum[k] += b.cwiseProduct(b);
      radial_sum[k] += radial[k];
    }
    ++views;
    draws += static_cast<int>(errors.size());
    noise_dof += static_cast<double>(errors.size()) - 1;
    inverse_draws += 1.0 / static_cast<double>(errors.size());
  }
  std::array<CornerStats, 4> Stats() const {
    std::array<CornerStats, 4> s;
    if (views == 0) return s;
    double view_sq = 0;
    for (int k = 0; k < 4; ++k) {
      s[k].bias = bias_sum[k] / views;
      const Eigen::Vector2d var = bias_sq_sum[k] / views - s[k].bias.cwiseProduct(s[k].bias);
      view_sq += std::max(0.0, var.x()) + std::max(0.0, var.y());
      const Eigen::Vector2d r = radial_sum[k].normalized();
      s[k].radial_px = s[k].bias.dot(r);
      s[k].tangent_px = s[k].bias.dot(Eigen::Vector2d(-r.y(), r.x()));
    }
    // Noise: the residual variance about each view's mean, per corner (|e|^2 sums two axes), on
    // its degrees of freedom. View-to-view: the spread of the view means less the noise each of
    // them still holds (noise^2 / draws, averaged over the views).
    const double noise_sq = noise_dof > 0 ? noise_sq_sum / (4.0 * noise_dof) : NAN;
    const double view_noise_sq = std::isnan(noise_sq) ? 0.0 : noise_sq * inverse_draws / views;
    for (int k = 0; k < 4; ++k) {
      s[k].view_rms_px = std::sqrt(std::max(0.0, view_sq / 4 - view_noise_sq));
      s[k].noise_rms_px = std::sqrt(noise_sq);
    }
    return s;
  }
};

// One view of a case: the board pose, the exact corners and their outward directions.
struct TagView {
  BoardView board;
  std::array<Eigen::Vector2d, 4> truth, radial;
  double view_angle_deg = 0;
};

bool MakeView(const CornerBiasCase& c, const Eigen::Vector2d& centre_px, const AprilGrid& grid,
              const std::shared_ptr<const TagFamily>& family, const CameraIntrinsics& k, TagView* v,
              std::string* why) {
  // The tag centre on the ray of centre_px at the depth that gives tag_px.
  const double depth = k.fku_px * grid.tag_size_m / c.tag_px;
  const Eigen::Vector3d ray =
      k.Matrix().inverse() * Eigen::Vector3d(centre_px.x(), centre_px.y(), 1);
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  const Eigen::Vector3d centre_in_board = (corners[0] + corners[2]) / 2;
  v->board.grid = grid;
  v->board.family = family;
  // Facing the camera (board y up in the image, its normal toward the camera), then roll, tilt.
  v->board.cam_from_board.rotation = RotX(c.tilt_deg * kDeg) * RotX(M_PI) * RotZ(c.roll_deg * kDeg);
  v->board.cam_from_board.translation =
      depth * ray / ray.z() - v->board.cam_from_board.rotation * centre_in_board;
  const Eigen::Vector3d normal = v->board.cam_from_board.rotation.col(2);
  const Eigen::Vector3d sight = (depth * ray / ray.z()).normalized();
  v->view_angle_deg = std::acos(std::min(1.0, std::abs(normal.dot(sight)))) / kDeg;
  Eigen::Vector2d centre;
  bool in_front = ProjectPoint(k, v->board.cam_from_board * centre_in_board, &centre);
  for (int i = 0; i < 4 && in_front; ++i) {
    in_front = ProjectPoint(k, v->board.cam_from_board * corners[i], &v->truth[i]);
    v->radial[i] = (v->truth[i] - centre).normalized();
  }
  if (!in_front && why) *why = "the tag is behind the camera";
  return in_front;
}

double PolygonArea(const std::array<Eigen::Vector2d, 4>& q) {
  double a = 0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = q[k];
    const Eigen::Vector2d& r = q[(k + 1) % 4];
    a += p.x() * r.y() - r.x() * p.y();
  }
  return std::abs(a) / 2;
}

}  // namespace

bool CornerBiasOptions::Check(std::string* why) const {
  std::string msg;
  if (draws < 1) msg = "draws must be >= 1";
  if (views < 1) msg = "views must be >= 1";
  if (!(noise_sigma_gray >= 0)) msg = "noise_sigma_gray must be >= 0";
  if (msg.empty()) return camera.Check(why);
  if (why) *why = msg;
  return false;
}

CornerBiasResult MeasureCornerBias(const CornerBiasCase& c, int case_index,
                                   const CornerBiasOptions& options) {
  CornerBiasResult result;
  if (!options.Check(&result.message)) return result;
  AprilGrid grid;
  grid.tag_rows = grid.tag_cols = 1;
  grid.tag_size_m = 0.1;
  auto family = TagFamily::Create(grid.family, grid.black_tag_border, &result.message);
  if (!family) return result;
  const CameraIntrinsics& k = options.camera;
  TagView view0;
  if (!MakeView(c, c.centre_px, grid, family, k, &view0, &result.message)) return result;
  result.view_angle_deg = view0.view_angle_deg;
  // The exact black area of view 0: every black cell of tag 0's bitmap, projected.
  const double cell = grid.tag_size_m / family->width_at_border();
  const int start = family->border_start();
  const Rigid3& cam_from_board = view0.board.cam_from_board;
  for (int row = 0; row < family->total_width(); ++row) {
    for (int col = 0; col < family->total_width(); ++col) {
      if (family->IsWhite(0, col, row)) continue;
      // Bitmap row 0 is the top: board y grows upward (corner 3 = top-left has y = size).
      const double x0 = (col - start) * cell;
      const double y1 = grid.tag_size_m - (row - start) * cell;
      const double xs[4] = {x0, x0 + cell, x0 + cell, x0};
      const double ys[4] = {y1 - cell, y1 - cell, y1, y1};
      std::array<Eigen::Vector2d, 4> q;
      for (int v = 0; v < 4; ++v)
        ProjectPoint(k, cam_from_board * Eigen::Vector3d(xs[v], ys[v], 0), &q[v]);
      result.black_area_px2 += PolygonArea(q);
    }
  }

  RenderOptions render;
  render.width = options.width;
  render.height = options.height;
  render.supersample = options.supersample;
  render.blur_sigma_px = c.blur_sigma_px;
  auto renderer = FrameRenderer::Create(k, render, &result.message);
  if (!renderer) return result;
  // The renderer alone: the noise-free black area of view 0 over the pixels whose centre sees the
  // board within 0.7 of the white margin around the black square (the margin is tag_spacing *
  // size wide; blur spreads the black < 3 sigma px into it).
  GrayImage image;
  if (!renderer->Render({view0.board}, nullptr, &image, &result.message)) return result;
  {
    const double margin = 0.7 * grid.tag_spacing * grid.tag_size_m;
    const Eigen::Matrix3d& r = cam_from_board.rotation;
    Eigen::Matrix3d h;  // Board (x, y, 1) -> camera ray.
    h << r.col(0), r.col(1), cam_from_board.translation;
    const Eigen::Matrix3d board_from_pixel = h.inverse() * k.Matrix().inverse();
    const double span = render.white_gray - render.black_gray;
    for (int j = 0; j < image.height; ++j) {
      for (int i = 0; i < image.width; ++i) {
        const Eigen::Vector3d b = board_from_pixel * Eigen::Vector3d(i, j, 1);
        const double bx = b.x() / b.z(), by = b.y() / b.z();
        if (bx < -margin || by < -margin || bx > grid.tag_size_m + margin ||
            by > grid.tag_size_m + margin)
          continue;
        result.rendered_black_area_px2 += (render.white_gray - image.at(i, j)) / span;
      }
    }
  }

  AprilTagOptions detector_options;
  detector_options.quad_decimate = options.quad_decimate;
  auto detector = AprilTagDetector::Create(detector_options, &result.message);
  if (!detector) return result;
  CornerRefineOptions refine;
  refine.width_at_border = family->width_at_border();
  render.noise_sigma_gray = options.noise_sigma_gray;
  renderer = FrameRenderer::Create(k, render, &result.message);
  if (!renderer) return result;
  TagPattern pattern;
  if (!TagPattern::FromFamily(*family, 0, grid.tag_spacing * family->width_at_border(), 0.0,
                              &pattern, &result.message))
    return result;
  const PhotometricFitOptions fit_options;
  CaseSums raw, refined, photometric;
  double crlb_sum = 0, blur_sum = 0;
  int timed = 0;
  using Clock = std::chrono::steady_clock;
  auto micros = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::micro>(b - a).count();
  };
  for (int v = 0; v < options.views; ++v) {
    const uint64_t view_seed = Mix64(options.seed ^ Mix64(1000003ULL * case_index + v));
    Rng shift_rng(view_seed);
    const Eigen::Vector2d shift(shift_rng.Uniform(-0.5, 0.5), shift_rng.Uniform(-0.5, 0.5));
    TagView view = view0;  // View 0 is the case's own; the others are shifted.
    if (v > 0 && !MakeView(c, c.centre_px + shift, grid, family, k, &view, &result.message))
      return result;
    std::vector<std::array<Eigen::Vector2d, 4>> raw_errors, refined_errors, photometric_errors;
    for (int d = 0; d < options.draws; ++d) {
      Rng rng(Mix64(view_seed + 1 + d));
      if (!renderer->Render({view.board}, &rng, &image, &result.message)) return result;
      const Clock::time_point t0 = Clock::now();
      const std::vector<TagDetection> tags = detector->Detect(image);
      const Clock::time_point t1 = Clock::now();
      for (TagDetection tag : tags) {
        if (tag.id != 0) continue;
        const std::array<Eigen::Vector2d, 4> raw_corners = tag.corners;
        std::array<Eigen::Vector2d, 4> e;
        for (int i = 0; i < 4; ++i) e[i] = tag.corners[i] - view.truth[i];
        const Clock::time_point t2 = Clock::now();
        const bool refined_ok = RefineTagCorners(image, refine, &tag);
        const Clock::time_point t3 = Clock::now();
        const PhotometricFitResult fit =
            FitTagPhotometric(image, pattern, raw_corners, fit_options,
                              options.lens_aware_fit ? &options.camera : nullptr);
        const Clock::time_point t4 = Clock::now();
        result.detect_us += micros(t0, t1);
        result.refine_us += micros(t2, t3);
        result.photometric_us += micros(t3, t4);
        ++timed;
        ++result.photometric_failures[static_cast<int>(fit.failure)];
        if (fit.ok()) {
          std::array<Eigen::Vector2d, 4> ep;
          for (int i = 0; i < 4; ++i) {
            ep[i] = fit.corners[i] - view.truth[i];
            crlb_sum += fit.crlb_px[i] / 4;
          }
          blur_sum += fit.blur_px;
          result.photometric_iterations += fit.iterations;
          photometric_errors.push_back(ep);
        }
        if (!refined_ok) break;
        raw_errors.push_back(e);
        for (int i = 0; i < 4; ++i) e[i] = tag.corners[i] - view.truth[i];
        refined_errors.push_back(e);
        break;
      }
    }
    raw.AddView(raw_errors, view.radial);
    refined.AddView(refined_errors, view.radial);
    photometric.AddView(photometric_errors, view.radial);
  }
  if (timed > 0) {
    result.detect_us /= timed;
    result.refine_us /= timed;
    result.photometric_us /= timed;
  }
  result.photometric = photometric.Stats();
  result.photometric_draws = photometric.draws;
  if (photometric.draws > 0) {
    result.photometric_crlb_px = crlb_sum / photometric.draws;
    result.photometric_blur_px = blur_sum / photometric.draws;
    result.photometric_iterations /= photometric.draws;
  }
  result.detected_draws = refined.draws;
  result.raw = raw.Stats();
  result.refined = refined.Stats();
  result.ok = refined.draws > 0;
  if (!result.ok) result.message = "the tag was detected in none of the draws";
  return result;
}

std::vector<CornerBiasCase> DefaultCornerBiasCases() {
  std::vector<CornerBiasCase> cases;
  const CornerBiasCase base;
  for (double tilt : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0}) {
    for (double roll : {0.0, 22.5}) {
      CornerBiasCase c = base;
      c.tilt_deg = tilt;
      c.roll_deg = roll;
      cases.push_back(c);
    }
  }
  for (double px : {12.0, 16.0, 24.0, 48.0, 64.0, 96.0}) {
    CornerBiasCase c = base;
    c.tag_px = px;
    cases.push_back(c);
  }
  for (double blur : {0.0, 0.25, 1.0, 1.5}) {
    CornerBiasCase c = base;
    c.blur_sigma_px = blur;
    cases.push_back(c);
  }
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(80, 60), Eigen::Vector2d(560, 60),
                                    Eigen::Vector2d(80, 420), Eigen::Vector2d(200, 300)}) {
    CornerBiasCase c = base;
    c.centre_px = at;
    cases.push_back(c);
  }
  return cases;
}

}  // namespace calibench
