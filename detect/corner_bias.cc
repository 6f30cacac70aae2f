#include "detect/corner_bias.h"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <optional>

#include "camera/pose.h"
#include "detect/apriltag_detector.h"
#include "detect/frame_detector.h"
#include "sim/render.h"
#include "sim/tag_family.h"
#include "sim/target.h"
#include "util/random.h"

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
  double error_sq_sum = 0;   // Over views, draws and corners, of |e|^2.
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
      for (const auto& e : errors) {
        noise_sq_sum += (e[k] - b).squaredNorm();
        error_sq_sum += e[k].squaredNorm();
      }
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
  double RmsPerAxis() const { return draws > 0 ? std::sqrt(error_sq_sum / (8.0 * draws)) : NAN; }
};

// One view of a case: the board pose, the exact corners and their outward directions.
struct TagView {
  BoardView board;
  std::array<Eigen::Vector2d, 4> truth, radial;
  double view_angle_deg = 0;
};

// The tag centre on the ray of centre_px at `depth` (m): along the optical axis, or along the ray
// for a camera whose views face the line of sight (CornerBiasCamera::faces_line_of_sight).
bool MakeView(const CornerBiasCase& c, const Eigen::Vector2d& centre_px, double depth,
              const AprilGrid& grid, const std::shared_ptr<const TagFamily>& family,
              const CornerBiasCamera& camera, TagView* v, std::string* why) {
  const CameraIntrinsics& k = camera.intrinsics;
  Eigen::Vector3d centre_in_cam;
  Eigen::Matrix3d turn = Eigen::Matrix3d::Identity();  // Optical axis -> line of sight.
  bool valid = false;
  if (camera.faces_line_of_sight) {
    Eigen::Vector3d ray;
    valid = UnprojectToRay(k, centre_px, &ray);
    turn = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), ray).toRotationMatrix();
    centre_in_cam = depth * ray;
  } else {
    Eigen::Vector2d ray_xy;
    valid = UnprojectPixel(k, centre_px, &ray_xy);
    centre_in_cam = depth * ray_xy.homogeneous();
  }
  if (!valid) {
    if (why) *why = "the tag centre is outside the lens's valid region";
    return false;
  }
  const std::vector<Eigen::Vector3d> corners = grid.CornersInBoard();
  const Eigen::Vector3d centre_in_board = (corners[0] + corners[2]) / 2;
  v->board.grid = grid;
  v->board.family = family;
  // Facing the camera (board y up in the image, its normal toward the camera), then roll, tilt.
  v->board.cam_from_board.rotation =
      turn * RotX(c.tilt_deg * kDeg) * RotX(M_PI) * RotZ(c.roll_deg * kDeg);
  v->board.cam_from_board.translation =
      centre_in_cam - v->board.cam_from_board.rotation * centre_in_board;
  const Eigen::Vector3d normal = v->board.cam_from_board.rotation.col(2);
  v->view_angle_deg =
      std::acos(std::min(1.0, std::abs(normal.dot(centre_in_cam.normalized())))) / kDeg;
  Eigen::Vector2d centre;
  bool in_front = ProjectPoint(k, v->board.cam_from_board * centre_in_board, &centre);
  for (int i = 0; i < 4 && in_front; ++i) {
    in_front = ProjectPoint(k, v->board.cam_from_board * corners[i], &v->truth[i]);
    v->radial[i] = (v->truth[i] - centre).normalized();
  }
  if (!in_front && why) *why = "the tag is behind the camera";
  return in_front;
}

// The depth at which the tag, fronto-parallel and unrolled at centre_px, shows a mean side of
// tag_px pixels through the lens (a few fixed-point steps: the side is ~ 1 / depth).
bool DepthForTagPx(const CornerBiasCase& c, const Eigen::Vector2d& centre_px, const AprilGrid& grid,
                   const std::shared_ptr<const TagFamily>& family, const CornerBiasCamera& camera,
                   double* depth, std::string* why) {
  CornerBiasCase flat = c;
  flat.tilt_deg = flat.roll_deg = 0;
  *depth = camera.intrinsics.fku_px * grid.tag_size_m / c.tag_px;
  for (int it = 0; it < 6; ++it) {
    TagView v;
    if (!MakeView(flat, centre_px, *depth, grid, family, camera, &v, why)) return false;
    double side = 0;
    for (int i = 0; i < 4; ++i) side += (v.truth[(i + 1) % 4] - v.truth[i]).norm() / 4;
    if (!(side > 0)) break;
    *depth *= side / c.tag_px;
  }
  return true;
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

const char* CornerBiasLensName(CornerBiasLens lens) {
  switch (lens) {
    case CornerBiasLens::kNone:
      return "none";
    case CornerBiasLens::kRadTanEuroc:
      return "radtan_euroc";
    case CornerBiasLens::kEquidistant:
      return "equidistant";
    case CornerBiasLens::kDoubleSphere190:
      return "double_sphere_190";
  }
  return "unknown";
}

CornerBiasCamera CornerBiasCamera::Of(CornerBiasLens lens) {
  CornerBiasCamera c;
  switch (lens) {
    case CornerBiasLens::kNone:
      c.intrinsics = CameraIntrinsics{800.0, 800.0, 90.0, 319.5, 239.5};
      c.default_centre_px = Eigen::Vector2d(319.5, 239.5);
      break;
    case CornerBiasLens::kRadTanEuroc:
      c.intrinsics = CameraIntrinsics{458.0, 457.0, 90.0, 367.0, 248.0, -0.28, 0.074};
      c.width = 752;
      c.default_centre_px = Eigen::Vector2d(150, 120);
      break;
    case CornerBiasLens::kEquidistant:
      c.intrinsics = CameraIntrinsics{300.0, 300.0, 90.0, 375.5, 239.5, 0.01, -0.002};
      c.intrinsics.family = LensFamily::kEquidistant;
      c.width = 752;
      c.default_centre_px = Eigen::Vector2d(150, 120);
      break;
    case CornerBiasLens::kDoubleSphere190: {
      // 95 deg lands 1.1354 f from the centre: 480 px.
      c.intrinsics = CameraIntrinsics{423.0, 423.0, 90.0, 511.5, 511.5};
      c.intrinsics.family = LensFamily::kDoubleSphere;
      c.intrinsics.xi = 0.6;
      c.intrinsics.alpha = 0.6;
      c.width = c.height = 1024;
      c.faces_line_of_sight = true;
      // At 95 deg from the axis, up and to the left of the centre (azimuth 225 deg).
      const double theta = 95 * kDeg, azimuth = 225 * kDeg;
      const Eigen::Vector3d at(std::sin(theta) * std::cos(azimuth),
                               std::sin(theta) * std::sin(azimuth), std::cos(theta));
      ProjectPoint(c.intrinsics, at, &c.default_centre_px);
      break;
    }
  }
  return c;
}

const char* CornerStageName(CornerStage stage, bool corner_squares) {
  switch (stage) {
    case CornerStage::kRaw:
      return "raw";
    case CornerStage::kEdgeFit:
      return corner_squares ? "saddle" : "edge_fit";
    case CornerStage::kPhotometric:
      return "photometric";
    case CornerStage::kLensAware:
      return "lens_aware";
  }
  return "unknown";
}

bool CornerBiasOptions::Check(std::string* why) const {
  std::string msg;
  if (draws < 1) msg = "draws must be >= 1";
  if (views < 1) msg = "views must be >= 1";
  if (!(noise_sigma_gray >= 0)) msg = "noise_sigma_gray must be >= 0";
  if (supersample < 1) msg = "supersample must be >= 1";
  if (!(quad_decimate >= 1)) msg = "quad_decimate must be >= 1";
  if (msg.empty()) return true;
  if (why) *why = msg;
  return false;
}

namespace {

// The exact black area of view 0 (every black cell of tag 0's bitmap, projected) and the one
// rendered without noise, over the pixels whose centre sees the board within 0.7 of the white
// margin around the black square (the margin is tag_spacing * size wide; blur spreads the black
// < 3 sigma px into it). Pinhole cameras without corner squares only.
void MeasureBlackArea(const TagView& view0, const TagFamily& family, const CameraIntrinsics& k,
                      const FrameRenderer& renderer, const RenderOptions& render,
                      CornerBiasResult* result) {
  const AprilGrid& grid = view0.board.grid;
  const double cell = grid.tag_size_m / family.width_at_border();
  const int start = family.border_start();
  const Rigid3& cam_from_board = view0.board.cam_from_board;
  double exact = 0;
  for (int row = 0; row < family.total_width(); ++row) {
    for (int col = 0; col < family.total_width(); ++col) {
      if (family.IsWhite(0, col, row)) continue;
      // Bitmap row 0 is the top: board y grows upward (corner 3 = top-left has y = size).
      const double x0 = (col - start) * cell;
      const double y1 = grid.tag_size_m - (row - start) * cell;
      const double xs[4] = {x0, x0 + cell, x0 + cell, x0};
      const double ys[4] = {y1 - cell, y1 - cell, y1, y1};
      std::array<Eigen::Vector2d, 4> q;
      for (int v = 0; v < 4; ++v)
        ProjectPoint(k, cam_from_board * Eigen::Vector3d(xs[v], ys[v], 0), &q[v]);
      exact += PolygonArea(q);
    }
  }
  GrayImage image;
  std::string why;
  if (!renderer.Render({view0.board}, nullptr, &image, &why)) return;
  const double margin = 0.7 * grid.tag_spacing * grid.tag_size_m;
  const Eigen::Matrix3d& r = cam_from_board.rotation;
  Eigen::Matrix3d h;  // Board (x, y, 1) -> camera ray.
  h << r.col(0), r.col(1), cam_from_board.translation;
  const Eigen::Matrix3d board_from_pixel = h.inverse() * k.Matrix().inverse();
  const double span = render.white_gray - render.black_gray;
  double rendered = 0;
  for (int j = 0; j < image.height; ++j) {
    for (int i = 0; i < image.width; ++i) {
      const Eigen::Vector3d b = board_from_pixel * Eigen::Vector3d(i, j, 1);
      const double bx = b.x() / b.z(), by = b.y() / b.z();
      if (bx < -margin || by < -margin || bx > grid.tag_size_m + margin ||
          by > grid.tag_size_m + margin)
        continue;
      rendered += (render.white_gray - image.at(i, j)) / span;
    }
  }
  result->black_area_px2 = exact;
  result->rendered_black_area_px2 = rendered;
}

// One stage's accumulators over the case.
struct StageSums {
  CaseSums sums;
  std::vector<std::array<Eigen::Vector2d, 4>> view_errors;  // This view's draws.
  double crlb_sum = 0, us_sum = 0;
  int attempts = 0;
};

// The study's target: one tag (id 0) of 0.1 m with the case's border and corner squares.
AprilGrid SingleTagGrid(const CornerBiasCase& c) {
  AprilGrid grid;
  grid.tag_rows = grid.tag_cols = 1;
  grid.tag_size_m = 0.1;
  grid.black_tag_border = c.black_border_bits;
  grid.corner_squares = c.corner_squares;
  return grid;
}

// The crop around the tag in view0: its outline (white margin included) projected along the sides
// (a lens bends them), padded by 8 + 4 blur px, clipped to the image. None when less than 16 px
// of it is in the image.
struct CropBox {
  int x0, y0, x1, y1;  // Inclusive pixel bounds in the frame.
};
std::optional<CropBox> TagCrop(const CornerBiasCase& c, const CornerBiasCamera& camera,
                               const AprilGrid& grid, const TagView& view0) {
  CropBox box{camera.width, camera.height, 0, 0};
  const double m = (grid.tag_spacing + 0.5) * grid.tag_size_m, s = grid.tag_size_m;
  const std::array<Eigen::Vector3d, 4> outline = {
      Eigen::Vector3d(-m, -m, 0), Eigen::Vector3d(s + m, -m, 0), Eigen::Vector3d(s + m, s + m, 0),
      Eigen::Vector3d(-m, s + m, 0)};
  const double pad = 8 + 4 * c.blur_sigma_px;
  for (int i = 0; i < 4; ++i) {
    for (double t : {0.0, 0.25, 0.5, 0.75}) {
      const Eigen::Vector3d in_board = outline[i] + t * (outline[(i + 1) % 4] - outline[i]);
      Eigen::Vector2d q;
      if (!ProjectPoint(camera.intrinsics, view0.board.cam_from_board * in_board, &q)) continue;
      box.x0 = std::min(box.x0, static_cast<int>(std::floor(q.x() - pad)));
      box.y0 = std::min(box.y0, static_cast<int>(std::floor(q.y() - pad)));
      box.x1 = std::max(box.x1, static_cast<int>(std::ceil(q.x() + pad)));
      box.y1 = std::max(box.y1, static_cast<int>(std::ceil(q.y() + pad)));
    }
  }
  box.x0 = std::max(0, box.x0), box.y0 = std::max(0, box.y0);
  box.x1 = std::min(camera.width - 1, box.x1), box.y1 = std::min(camera.height - 1, box.y1);
  if (box.x1 - box.x0 < 16 || box.y1 - box.y0 < 16) return std::nullopt;
  return box;
}

// The frame detectors of the refining stages, as the study configures them (nullptr: the stage
// does not run; the lens-aware one needs a lens). False (and *why) when one cannot be made.
bool StageDetectors(const CornerBiasCase& c, const AprilGrid& grid,
                    const CornerBiasOptions& options, const CameraIntrinsics& crop_camera,
                    std::array<std::unique_ptr<FrameDetector>, kNumCornerStages>* detectors,
                    std::string* why) {
  for (const CornerStage stage :
       {CornerStage::kEdgeFit, CornerStage::kPhotometric, CornerStage::kLensAware}) {
    if (stage == CornerStage::kLensAware && c.lens == CornerBiasLens::kNone) continue;
    FrameDetectorOptions o;
    o.detector.quad_decimate = options.quad_decimate;
    o.refinement = stage == CornerStage::kEdgeFit ? CornerRefinement::kEdgeFit
                                                  : CornerRefinement::kPhotometric;
    o.refine.curved_edges =
        c.lens == CornerBiasLens::kEquidistant || c.lens == CornerBiasLens::kDoubleSphere190;
    if (stage == CornerStage::kLensAware) o.camera = crop_camera;
    (*detectors)[static_cast<int>(stage)] = FrameDetector::Create({grid}, o, why);
    if (!(*detectors)[static_cast<int>(stage)]) return false;
  }
  return true;
}

// One draw's frame, cropped: the image, where its pixel (0, 0) is in the frame, and the tag's
// exact corners in the frame.
struct CroppedDraw {
  const GrayImage& image;
  const Eigen::Vector2d& crop_origin;
  const std::array<Eigen::Vector2d, 4>& truth;
};

// Every stage on one draw: AprilTag alone, then each refining detector, timed; the errors of the
// tag's corners (when found) go to the stage's view_errors, refusals to result->stages.
void RunStages(const CroppedDraw& draw, const AprilTagDetector& raw_detector,
               const std::array<std::unique_ptr<FrameDetector>, kNumCornerStages>& detectors,
               std::array<StageSums, kNumCornerStages>* sums, CornerBiasResult* result) {
  using Clock = std::chrono::steady_clock;
  auto micros = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::micro>(b - a).count();
  };
  const GrayImage& image = draw.image;
  const uint8_t* crop = image.pixels.data();
  const int crop_w = image.width, crop_h = image.height;
  {
    StageSums& s = (*sums)[static_cast<int>(CornerStage::kRaw)];
    const Clock::time_point t0 = Clock::now();
    const std::vector<TagDetection> tags = raw_detector.Detect(crop, crop_w, crop_h, image.width);
    s.us_sum += micros(t0, Clock::now());
    ++s.attempts;
    for (const TagDetection& tag : tags) {
      if (tag.id != 0) continue;
      std::array<Eigen::Vector2d, 4> e;
      for (int i = 0; i < 4; ++i) e[i] = tag.corners[i] + draw.crop_origin - draw.truth[i];
      s.view_errors.push_back(e);
      break;
    }
  }
  for (int st = 1; st < kNumCornerStages; ++st) {
    if (!detectors[st]) continue;
    StageSums& s = (*sums)[st];
    DetectionCounts counts;
    const Clock::time_point t0 = Clock::now();
    const std::vector<Observation> obs =
        detectors[st]->Detect(crop, crop_w, crop_h, image.width, &counts);
    s.us_sum += micros(t0, Clock::now());
    ++s.attempts;
    CornerStageResult& out = result->stages[st];
    for (int f = 1; f < kNumFitFailures; ++f) out.refused[f] += counts.refused_tags[f];
    if (obs.size() != 4) continue;  // Points 0..3: the tag's four corners, sorted.
    std::array<Eigen::Vector2d, 4> e;
    for (int i = 0; i < 4; ++i) {
      e[i] = obs[i].pixel + draw.crop_origin - draw.truth[obs[i].point_id];
      if (std::isfinite(obs[i].crlb_px)) s.crlb_sum += obs[i].crlb_px / 4;
    }
    s.view_errors.push_back(e);
  }
}

// Each stage's figures from its sums; result->ok when some stage found the tag.
void FinishStages(const std::array<StageSums, kNumCornerStages>& sums,
                  const std::array<std::unique_ptr<FrameDetector>, kNumCornerStages>& detectors,
                  CornerBiasResult* result) {
  for (int st = 0; st < kNumCornerStages; ++st) {
    CornerStageResult& out = result->stages[st];
    const StageSums& s = sums[st];
    out.run = st == 0 || detectors[st] != nullptr;
    if (!out.run) continue;
    out.detections = s.sums.draws;
    out.failed = s.attempts - s.sums.draws;
    out.corners = s.sums.Stats();
    out.rms_px = s.sums.RmsPerAxis();
    out.us_per_tag = s.attempts > 0 ? s.us_sum / s.attempts : 0;
    if (st >= static_cast<int>(CornerStage::kPhotometric) && s.sums.draws > 0)
      out.crlb_px = s.crlb_sum / s.sums.draws;
    if (out.detections > 0) result->ok = true;
  }
}

}  // namespace

CornerBiasResult MeasureCornerBias(const CornerBiasCase& c, int case_index,
                                   const CornerBiasOptions& options) {
  CornerBiasResult result;
  if (!options.Check(&result.message)) return result;
  if (c.black_border_bits != 1 && c.black_border_bits != 2) {
    result.message = "black_border_bits must be 1 or 2";
    return result;
  }
  const CornerBiasCamera camera = CornerBiasCamera::Of(c.lens);
  const CameraIntrinsics& k = camera.intrinsics;
  const Eigen::Vector2d centre_px =
      c.centre_px.allFinite() ? c.centre_px : camera.default_centre_px;
  const AprilGrid grid = SingleTagGrid(c);
  auto family = TagFamily::Create(grid.family, grid.black_tag_border, &result.message);
  if (!family) return result;
  double depth = 0;
  TagView view0;
  if (!DepthForTagPx(c, centre_px, grid, family, camera, &depth, &result.message) ||
      !MakeView(c, centre_px, depth, grid, family, camera, &view0, &result.message))
    return result;
  result.view_angle_deg = view0.view_angle_deg;
  result.centre_px = centre_px;
  for (int i = 0; i < 4; ++i)
    result.tag_edge_px += (view0.truth[(i + 1) % 4] - view0.truth[i]).norm() / 4;

  // Every stage sees the crop around the tag (its white margin, squares and blur, plus 8 px): the
  // detector's cost is per pixel, and the rest of the frame is a flat white board.
  const std::optional<CropBox> crop = TagCrop(c, camera, grid, view0);
  if (!crop) {
    result.message = "the tag is outside the image";
    return result;
  }
  const auto [x0, y0, x1, y1] = *crop;
  const Eigen::Vector2d crop_origin(x0, y0);
  CameraIntrinsics crop_camera = k;  // The same lens, its principal point in crop pixels.
  crop_camera.u0_px -= x0;
  crop_camera.v0_px -= y0;
  // The renderer draws the crop only (the same pixels as the frame's, at a fraction of the cost).
  RenderOptions render;
  render.width = x1 - x0 + 1;
  render.height = y1 - y0 + 1;
  render.supersample = options.supersample;
  render.blur_sigma_px = c.blur_sigma_px;
  auto renderer = FrameRenderer::Create(crop_camera, render, &result.message);
  if (!renderer) return result;
  if (c.lens == CornerBiasLens::kNone && !c.corner_squares)
    MeasureBlackArea(view0, *family, crop_camera, *renderer, render, &result);
  AprilTagOptions raw_options;
  raw_options.black_border_bits = c.black_border_bits;
  raw_options.quad_decimate = options.quad_decimate;
  auto raw_detector = AprilTagDetector::Create(raw_options, &result.message);
  if (!raw_detector) return result;
  // The frame detectors of the refining stages (nullptr: the stage does not run).
  std::array<std::unique_ptr<FrameDetector>, kNumCornerStages> detectors;
  if (!StageDetectors(c, grid, options, crop_camera, &detectors, &result.message)) return result;
  render.noise_sigma_gray = options.noise_sigma_gray;
  renderer = FrameRenderer::Create(crop_camera, render, &result.message);
  if (!renderer) return result;

  std::array<StageSums, kNumCornerStages> sums;
  GrayImage image;
  for (int v = 0; v < options.views; ++v) {
    const uint64_t view_seed = Mix64(options.seed ^ Mix64(1000003ULL * case_index + v));
    Rng shift_rng(view_seed);
    const double shift_y = shift_rng.Uniform(-0.5, 0.5);  // y first (util/random.h).
    const Eigen::Vector2d shift(shift_rng.Uniform(-0.5, 0.5), shift_y);
    TagView view = view0;  // View 0 is the case's own; the others are shifted.
    if (v > 0 &&
        !MakeView(c, centre_px + shift, depth, grid, family, camera, &view, &result.message))
      return result;
    for (StageSums& s : sums) s.view_errors.clear();
    for (int d = 0; d < options.draws; ++d) {
      Rng rng(Mix64(view_seed + 1 + d));
      if (!renderer->Render({view.board}, &rng, &image, &result.message)) return result;
      RunStages({image, crop_origin, view.truth}, *raw_detector, detectors, &sums, &result);
    }
    for (StageSums& s : sums) s.sums.AddView(s.view_errors, view.radial);
  }
  FinishStages(sums, detectors, &result);
  const CornerStageResult& aware = result.stage(CornerStage::kLensAware);
  result.crlb_px = aware.run ? aware.crlb_px : result.stage(CornerStage::kPhotometric).crlb_px;
  if (!result.ok) result.message = "the tag was found by no stage in any draw";
  return result;
}

namespace {

// One case per value: `base` with one field set to it.
template <typename Set>
void AddVariations(const CornerBiasCase& base, std::initializer_list<double> values, Set set,
                   std::vector<CornerBiasCase>* cases) {
  for (double v : values) {
    CornerBiasCase c = base;
    set(&c, v);
    cases->push_back(c);
  }
}

}  // namespace

std::vector<CornerBiasCase> DefaultCornerBiasCases() {
  std::vector<CornerBiasCase> cases;
  const auto tilt = [](CornerBiasCase* c, double v) { c->tilt_deg = v; };
  const auto size = [](CornerBiasCase* c, double v) { c->tag_px = v; };
  const auto blur = [](CornerBiasCase* c, double v) { c->blur_sigma_px = v; };
  // AprilTag 3's 1-bit tag without a lens: every axis about the default sweeps' view.
  const CornerBiasCase base;
  for (double t : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0}) {
    CornerBiasCase tilted = base;
    tilted.tilt_deg = t;
    AddVariations(
        tilted, {0, 22.5}, [](CornerBiasCase* c, double v) { c->roll_deg = v; }, &cases);
  }
  AddVariations(base, {15, 20, 45, 60}, size, &cases);
  AddVariations(base, {0, 1, 1.5}, blur, &cases);
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(80, 60), Eigen::Vector2d(560, 60),
                                    Eigen::Vector2d(80, 420), Eigen::Vector2d(200, 300)}) {
    CornerBiasCase c = base;
    c.centre_px = at;
    cases.push_back(c);
  }
  // The other (lens, border, squares) families: tilt, size and blur about the same view.
  struct Family {
    CornerBiasLens lens;
    int border;
    bool squares;
  };
  for (const Family& f :
       {Family{CornerBiasLens::kNone, 2, false}, Family{CornerBiasLens::kNone, 2, true},
        Family{CornerBiasLens::kRadTanEuroc, 1, false},
        Family{CornerBiasLens::kRadTanEuroc, 2, true},
        Family{CornerBiasLens::kEquidistant, 1, false},
        Family{CornerBiasLens::kEquidistant, 2, true},
        Family{CornerBiasLens::kDoubleSphere190, 1, false},
        Family{CornerBiasLens::kDoubleSphere190, 2, true}}) {
    CornerBiasCase b = base;
    b.lens = f.lens;
    b.black_border_bits = f.border;
    b.corner_squares = f.squares;
    cases.push_back(b);
    AddVariations(b, {30, 60}, tilt, &cases);
    AddVariations(b, {15, 60}, size, &cases);
    AddVariations(b, {0, 1, 1.5}, blur, &cases);
  }
  return cases;
}

}  // namespace calibench
