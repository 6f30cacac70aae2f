#include "diagnostics/source_diagnostics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace calibench {
namespace {

constexpr std::array<std::pair<CornerErrorPart, const char*>, 5> kCornerErrorParts{
    {{CornerErrorPart::kAll, "all"},
     {CornerErrorPart::kX, "x"},
     {CornerErrorPart::kY, "y"},
     {CornerErrorPart::kTagTranslation, "tag_translation"},
     {CornerErrorPart::kTagShape, "tag_shape"}}};

// Replaces each pixel of `frame` listed in `errors` (index into the frame, reported minus exact)
// by exact + the part of its error `options` keeps.
void KeepErrorPart(const DiagnosticsOptions& options, const std::vector<int>& grid_of_point,
                   const std::vector<std::pair<size_t, Eigen::Vector2d>>& errors, Frame* frame) {
  using Part = CornerErrorPart;
  if (options.corner_error_part == Part::kAll && options.corner_error_grid < 0) return;
  const bool per_tag = options.corner_error_part == Part::kTagTranslation ||
                       options.corner_error_part == Part::kTagShape;
  std::map<int, std::pair<Eigen::Vector2d, int>> tag_mean;  // Tag (point id / 4) -> sum, count.
  if (per_tag) {
    for (const auto& [i, e] : errors) {
      auto& [sum, n] =
          tag_mean.try_emplace(frame->point_ids[i] / 4, Eigen::Vector2d::Zero(), 0).first->second;
      sum += e;
      ++n;
    }
  }
  for (const auto& [i, e] : errors) {
    const int point = frame->point_ids[i];
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    if (per_tag) {
      const auto& [sum, n] = tag_mean.at(point / 4);
      mean = sum / n;
    }
    Eigen::Vector2d kept = e;
    switch (options.corner_error_part) {
      case Part::kAll:
        break;
      case Part::kX:
        kept.y() = 0;
        break;
      case Part::kY:
        kept.x() = 0;
        break;
      case Part::kTagTranslation:
        kept = mean;
        break;
      case Part::kTagShape:
        kept = e - mean;
        break;
    }
    if (options.corner_error_grid >= 0 && grid_of_point[point] != options.corner_error_grid) {
      kept.setZero();
    }
    frame->pixels[i] += kept - e;
  }
}

// The corner-error decorator (header): the inner source's frames, edited once at creation.
class CornerErrorSource final : public MeasurementSource {
 public:
  CornerErrorSource(std::unique_ptr<MeasurementSource> inner, std::vector<Frame> frames)
      : inner_(std::move(inner)), frames_(std::move(frames)) {}
  int NumPoints() const override { return inner_->NumPoints(); }
  double Duration() const override { return inner_->Duration(); }
  const std::vector<double>& Breakpoints() const override { return inner_->Breakpoints(); }
  void Measure(double t, int segment, Frame* frame) const override { *frame = frames_[segment]; }
  bool HeldWithinSegments() const override { return true; }
  int NumFrames() const override { return static_cast<int>(frames_.size()); }
  void GetFrame(int k, Frame* frame) const override { *frame = frames_[k]; }

 private:
  std::unique_ptr<MeasurementSource> inner_;
  std::vector<Frame> frames_;
};

// `frame` with the corner-error edits (header, steps 1-3). A point whose exact
// projection (or its tag centre's) fails keeps its measured pixel.
Frame EditCornerErrors(Frame frame, const SceneTruth& scene, const std::vector<int>& grid_of_point,
                       const DiagnosticsOptions& options) {
  const double t = frame.time_s;
  const CameraIntrinsics intrinsics = scene.IntrinsicsAt(t);
  const Rigid3 cam_from_points = scene.CamFromParentAt(t) * scene.ParentFromPoints(t);
  std::vector<std::pair<size_t, Eigen::Vector2d>> reported;  // (pixel index, reported - exact).
  for (size_t i = 0; i < frame.pixels.size(); ++i) {
    const int id = frame.point_ids[i];
    const int first_corner = id - id % 4;  // Tags own 4 consecutive points.
    const Eigen::Vector3d centre_in_points =
        (scene.points[first_corner] + scene.points[first_corner + 2]) / 2;
    Eigen::Vector2d exact, centre;
    if (!ProjectPoint(intrinsics, cam_from_points * scene.points[id], &exact) ||
        !ProjectPoint(intrinsics, cam_from_points * centre_in_points, &centre)) {
      continue;
    }
    const Eigen::Vector2d e = frame.pixels[i] - exact;
    if (e.norm() > options.corner_error_clip_px) {
      frame.pixels[i] = exact + e * (options.corner_error_clip_px / e.norm());
    }
    reported.emplace_back(i, frame.pixels[i] - exact);
  }
  KeepErrorPart(options, grid_of_point, reported, &frame);
  return frame;
}

// The tag-radial-bias decorator (header): the inner source's measurements plus the moves of the
// exact projections at the frame's time.
class TagRadialBiasSource final : public MeasurementSource {
 public:
  TagRadialBiasSource(std::unique_ptr<MeasurementSource> inner, const SceneTruth& scene,
                      double bias_px)
      : inner_(std::move(inner)), scene_(scene), bias_px_(bias_px) {}
  int NumPoints() const override { return inner_->NumPoints(); }
  double Duration() const override { return inner_->Duration(); }
  const std::vector<double>& Breakpoints() const override { return inner_->Breakpoints(); }
  void Measure(double t, int segment, Frame* frame) const override {
    inner_->Measure(t, segment, frame);
    AddMoves(frame);
  }
  bool HeldWithinSegments() const override { return inner_->HeldWithinSegments(); }
  int NumFrames() const override { return inner_->NumFrames(); }
  void GetFrame(int k, Frame* frame) const override {
    inner_->GetFrame(k, frame);
    AddMoves(frame);
  }

 private:
  void AddMoves(Frame* frame) const {
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> exact;
    if (!scene_.Observe(frame->time_s, &points, &exact, nullptr)) return;
    const std::vector<Eigen::Vector2d> moves = TagRadialMoves(bias_px_, exact);
    for (size_t i = 0; i < frame->pixels.size(); ++i) {
      const int id = frame->PointId(i);
      if (id >= 0 && id < static_cast<int>(moves.size())) frame->pixels[i] += moves[id];
    }
  }
  std::unique_ptr<MeasurementSource> inner_;
  SceneTruth scene_;
  double bias_px_;
};

}  // namespace

bool ParseCornerErrorPart(const std::string& name, CornerErrorPart* part) {
  for (const auto& [value, text] : kCornerErrorParts) {
    if (name == text) {
      *part = value;
      return true;
    }
  }
  return false;
}

std::string CornerErrorPartName(CornerErrorPart part) {
  for (const auto& [value, text] : kCornerErrorParts) {
    if (value == part) return text;
  }
  return "?";
}

std::string CornerErrorPartNames() {
  std::string names;
  for (const auto& [value, text] : kCornerErrorParts)
    names += (names.empty() ? "" : ", ") + std::string(text);
  return names;
}

bool DiagnosticsOptions::Check(std::string* why) const {
  if (!(corner_error_clip_px >= 0)) {
    if (why) *why = "corner_error_clip_px must be >= 0 (infinity: the measured corners)";
    return false;
  }
  if (corner_error_grid < -1) {
    if (why) *why = "corner_error_grid must be a grid's index (0, 1, ...) or -1 (every grid)";
    return false;
  }
  if (!std::isfinite(tag_radial_bias_px)) {
    if (why) *why = "tag_radial_bias_px must be finite, got " + std::to_string(tag_radial_bias_px);
    return false;
  }
  return true;
}

std::vector<Eigen::Vector2d> TagRadialMoves(double bias_px,
                                            const std::vector<Eigen::Vector2d>& exact) {
  std::vector<Eigen::Vector2d> moves(exact.size(), Eigen::Vector2d::Zero());
  if (bias_px == 0) return moves;
  const auto h = [](const Eigen::Vector2d& p) { return Eigen::Vector3d(p.x(), p.y(), 1.0); };
  for (size_t first = 0; first + 3 < exact.size(); first += 4) {
    const Eigen::Vector2d* c = exact.data() + first;
    const Eigen::Vector2d centre =
        h(c[0]).cross(h(c[2])).cross(h(c[1]).cross(h(c[3]))).hnormalized();
    if (!centre.allFinite()) continue;  // A degenerate (collapsed) tag: left as it is.
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d out = c[k] - centre;
      if (out.norm() > 0) moves[first + k] = bias_px * out.normalized();
    }
  }
  return moves;
}

std::unique_ptr<MeasurementSource> ApplyDiagnostics(std::unique_ptr<MeasurementSource> source,
                                                    const SceneTruth& scene,
                                                    const std::vector<AprilGrid>& grids,
                                                    const DiagnosticsOptions& options,
                                                    std::string* why) {
  if (!source || !options.Check(why)) return nullptr;
  if (options.CornerErrorActive()) {
    std::vector<int> grid_of_point;  // Grids' corners follow each other, 4 a tag.
    for (size_t g = 0; g < grids.size(); ++g)
      grid_of_point.insert(grid_of_point.end(), 4 * grids[g].NumTags(), static_cast<int>(g));
    if (options.corner_error_grid >= static_cast<int>(grids.size())) {
      if (why)
        *why = "corner_error_grid " + std::to_string(options.corner_error_grid) + " names no grid";
      return nullptr;
    }
    if (!source->HeldWithinSegments() ||
        source->NumFrames() + 1 != static_cast<int>(source->Breakpoints().size())) {
      if (why) *why = "the corner error needs frames held between breakpoints (rendered)";
      return nullptr;
    }
    std::vector<Frame> frames;
    for (int k = 0; k < source->NumFrames(); ++k) {
      Frame frame;
      source->GetFrame(k, &frame);
      if (frame.point_ids.size() != frame.pixels.size()) {
        if (why) *why = "the corner error needs frames that name their points (rendered)";
        return nullptr;
      }
      frames.push_back(EditCornerErrors(std::move(frame), scene, grid_of_point, options));
    }
    source = std::make_unique<CornerErrorSource>(std::move(source), std::move(frames));
  }
  if (options.tag_radial_bias_px != 0) {
    source =
        std::make_unique<TagRadialBiasSource>(std::move(source), scene, options.tag_radial_bias_px);
  }
  return source;
}

}  // namespace calibench
