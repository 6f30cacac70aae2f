#include "detect/frame_detector.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>

#include "detect/corner_squares.h"
#include "detect/plane_to_image.h"
#include "sim/tag_family.h"

namespace calibench {

namespace {
constexpr std::array<const char*, 3> kRefinementNames = {"none", "edge_fit", "photometric"};
}  // namespace

bool ParseCornerRefinement(const std::string& name, CornerRefinement* refinement) {
  for (size_t i = 0; i < kRefinementNames.size(); ++i) {
    if (name == kRefinementNames[i]) {
      *refinement = static_cast<CornerRefinement>(i);
      return true;
    }
  }
  return false;
}

const char* CornerRefinementName(CornerRefinement refinement) {
  const auto i = static_cast<size_t>(refinement);
  return i < kRefinementNames.size() ? kRefinementNames[i] : "unknown";
}

bool FrameDetectorOptions::Check(std::string* why) const {
  if (!(min_border_distance_px >= 0)) {
    if (why) *why = "min_border_distance_px must be >= 0";
    return false;
  }
  if (!(max_predicted_residual_ratio >= 1)) {
    if (why) *why = "max_predicted_residual_ratio must be >= 1";
    return false;
  }
  if (camera && !camera->Check(why)) return false;
  if (perspective_views_below_tags < 0) {
    if (why) *why = "perspective_views_below_tags must be >= 0";
    return false;
  }
  return detector.Check(why) && refine.Check(why) && photometric.Check(why);
}

std::unique_ptr<FrameDetector> FrameDetector::Create(const std::vector<AprilGrid>& grids,
                                                     const FrameDetectorOptions& options,
                                                     std::string* why) {
  if (!options.Check(why)) return nullptr;
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return nullptr;
  };
  if (grids.empty()) return fail("the target has no AprilGrid");
  std::unique_ptr<FrameDetector> d(new FrameDetector());
  d->options_ = options;
  d->options_.detector.family = grids[0].family;
  d->options_.detector.black_border_bits = grids[0].black_tag_border;
  for (size_t g = 0; g < grids.size(); ++g) {
    if (!grids[g].Check(why)) return nullptr;
    if (grids[g].family != grids[0].family) {
      return fail("grid " + std::to_string(g) + " uses " + grids[g].family + ", grid 0 uses " +
                  grids[0].family + ": one detector decodes one family");
    }
    if (grids[g].corner_squares != grids[0].corner_squares) {
      return fail("grid " + std::to_string(g) + (grids[g].corner_squares ? " has" : " has no") +
                  " corner squares, grid 0" + (grids[0].corner_squares ? " has" : " has none") +
                  ": one detector finds one layout");
    }
    if (grids[g].black_tag_border != grids[0].black_tag_border) {
      return fail("grid " + std::to_string(g) + " has a " +
                  std::to_string(grids[g].black_tag_border) + "-bit black border, grid 0 a " +
                  std::to_string(grids[0].black_tag_border) +
                  "-bit one: one detector decodes one border width");
    }
    GridIds ids{grids[g].first_id,
                grids[g].NumTags(),
                d->num_points_,
                grids[g].tag_rows,
                grids[g].tag_cols,
                grids[g].tag_spacing,
                {}};
    for (const Eigen::Vector3d& corner : grids[g].CornersInBoard())
      ids.corners_on_board.push_back(corner.head<2>());
    for (const GridIds& other : d->grids_) {
      if (ids.first_id < other.first_id + other.num_tags &&
          other.first_id < ids.first_id + ids.num_tags) {
        return fail("grid " + std::to_string(g) + " shares tag ids with an earlier grid");
      }
    }
    d->grids_.push_back(ids);
    d->num_points_ += 4 * ids.num_tags;
  }
  d->corner_squares_ = grids[0].corner_squares;
  d->family_ = TagFamily::Create(grids[0].family, grids[0].black_tag_border, why);
  if (!d->family_) return nullptr;
  d->options_.refine.width_at_border = d->family_->width_at_border();
  // Every tag's pattern for the photometric fit, once: tag index = point id / 4
  // (TagPattern::OnGrid). An id the family lacks keeps an empty pattern (its fit is refused).
  for (const AprilGrid& grid : grids) {
    for (int t = 0; t < grid.NumTags(); ++t) {
      TagPattern pattern;
      if (!TagPattern::OnGrid(*d->family_, grid.first_id + t, grid.tag_spacing, grid.corner_squares,
                              &pattern, nullptr))
        pattern.black.clear();
      d->patterns_.push_back(std::move(pattern));
    }
  }
  d->detector_ = AprilTagDetector::Create(d->options_.detector, why);
  if (!d->detector_) return nullptr;
  return d;
}

const CameraIntrinsics* FrameDetector::SquareLens() const {
  return options_.camera && options_.camera->IsDistorted() ? &*options_.camera : nullptr;
}

const FrameDetector::GridIds* FrameDetector::GridOf(int id) const {
  for (const GridIds& g : grids_) {
    if (id >= g.first_id && id < g.first_id + g.num_tags) return &g;
  }
  return nullptr;
}

int FrameDetector::PointId(int id, int corner) const {
  const GridIds* g = GridOf(id);
  return g ? g->first_point + 4 * (id - g->first_id) + corner : -1;
}

std::vector<Observation> FrameDetector::Detect(const GrayImage& image,
                                               DetectionCounts* counts) const {
  return Detect(image.pixels.data(), image.width, image.height, image.width, counts);
}

std::vector<Observation> FrameDetector::Detect(const uint8_t* pixels, int width, int height,
                                               int stride, DetectionCounts* counts) const {
  const GrayImageView view(pixels, width, height, stride);
  return RefineTags(view, FindTags(view), options_.camera ? &*options_.camera : nullptr, counts);
}

FoundTags FrameDetector::FindTags(const GrayImageView& view) const {
  std::vector<TagDetection> tags =
      detector_->Detect(view.data, view.width, view.height, view.stride);
  std::vector<bool> from_copy(tags.size(), false);
  if (corner_squares_) {
    FindTagsAmongSquares(view, {SquareLens(), options_.refine.curved_edges}, &tags, &from_copy);
  }
  FoundTags found = UsableTags(view, tags, from_copy);
  if (options_.camera &&
      static_cast<int>(found.tags.size()) < options_.perspective_views_below_tags) {
    FindTagsInPerspectiveViews(view, &tags, &from_copy);
    found = UsableTags(view, tags, from_copy);
  }
  return found;
}

FoundTags FrameDetector::UsableTags(const GrayImageView& view,
                                    const std::vector<TagDetection>& tags,
                                    const std::vector<bool>& from_copy) const {
  FoundTags found;
  std::map<int, int> times_seen;
  for (const TagDetection& tag : tags) ++times_seen[tag.id];
  for (size_t t = 0; t < tags.size(); ++t) {
    const TagDetection& tag = tags[t];
    if (PointId(tag.id, 0) < 0) {
      ++found.counts.unknown_tags;
      continue;
    }
    if (times_seen[tag.id] > 1) {  // Which of them is the grid's tag is unknown: drop them all.
      ++found.counts.duplicate_tags;
      continue;
    }
    if (NearBorder(tag.corners, view)) {
      ++found.counts.border_tags;
      continue;
    }
    found.tags.push_back(tag);
    found.from_copy.push_back(from_copy[t]);
  }
  return found;
}

void FrameDetector::FindTagsInPerspectiveViews(const GrayImageView& view,
                                               std::vector<TagDetection>* tags,
                                               std::vector<bool>* from_copy) const {
  std::set<int> known;  // Ids the image gave (usable or not): not taken again from a view.
  for (const TagDetection& tag : *tags) known.insert(tag.id);
  const CameraIntrinsics& camera = *options_.camera;
  if (views_size_ != std::array<int, 2>{view.width, view.height}) {
    views_ = PerspectiveViewsCovering(camera, view.width, view.height);
    views_size_ = {view.width, view.height};
  }
  for (const PerspectiveView& pv : views_) {
    // A view over a flat part of the image (the background, no board) holds no tag.
    if (ViewGrayRange(view, camera, pv) < kMinViewRangeGray) continue;
    const GrayImage resampled = ResampleView(view, camera, pv);
    std::vector<TagDetection> seen = detector_->Detect(resampled);
    std::vector<bool> seen_in_copy(seen.size(), false);
    // A perspective view is a pinhole image: squares map by homographies in its pixels.
    if (corner_squares_) FindTagsAmongSquares(resampled, {nullptr, false}, &seen, &seen_in_copy);
    std::map<int, int> times_in_view;  // An id decoded twice in a view: which one is it?
    for (const TagDetection& tag : seen) ++times_in_view[tag.id];
    for (const TagDetection& in_view : seen) {
      if (PointId(in_view.id, 0) < 0 || times_in_view[in_view.id] > 1 ||
          known.count(in_view.id) > 0) {
        continue;
      }
      TagDetection tag = in_view;
      bool maps = true;
      for (int k = 0; k < 4 && maps; ++k) {
        maps = ViewToImage(camera, pv, in_view.corners[k], &tag.corners[k]);
      }
      if (!maps) continue;
      known.insert(tag.id);
      tags->push_back(tag);
      from_copy->push_back(true);
    }
  }
}

bool FrameDetector::NearBorder(const std::array<Eigen::Vector2d, 4>& corners,
                               const GrayImageView& view) const {
  for (const Eigen::Vector2d& c : corners) {
    // Pixel centres at integers: the image spans [-0.5, width - 0.5] x [-0.5, height - 0.5].
    const double margin =
        std::min({c.x() + 0.5, c.y() + 0.5, view.width - 0.5 - c.x(), view.height - 0.5 - c.y()});
    if (!(margin >= options_.min_border_distance_px)) return true;
  }
  return false;
}

std::vector<Observation> FrameDetector::RefineTags(const GrayImageView& view,
                                                   const FoundTags& found,
                                                   const CameraIntrinsics* camera,
                                                   DetectionCounts* counts) const {
  DetectionCounts local = found.counts;
  std::vector<FittedTag> fitted;
  const bool photometric = options_.refinement == CornerRefinement::kPhotometric;
  const bool edge_fit = options_.refinement == CornerRefinement::kEdgeFit;
  std::map<int, FitFailure> refused;  // Decoded ids whose photometric fit was refused.
  for (size_t t = 0; t < found.tags.size(); ++t) {
    TagDetection tag = found.tags[t];
    FittedTag out{tag.id, {}, {}, std::numeric_limits<double>::quiet_NaN()};
    out.crlb_px.fill(std::numeric_limits<double>::quiet_NaN());
    if (photometric) {
      const PhotometricFitResult fit = FitTagPhotometric(view, patterns_[PointId(tag.id, 0) / 4],
                                                         tag.corners, options_.photometric, camera);
      if (!fit.ok()) {
        refused[tag.id] = fit.failure;  // Counted below, unless fitted again from its neighbours.
        continue;
      }
      tag.corners = fit.corners;
      out.crlb_px = fit.crlb_px;
      local.covered_tags += fit.outlier_pixels > 0 ? 1 : 0;
      out.residual_rms_gray = fit.residual_rms_gray;
    }
    if (edge_fit && !RefineTagCorners(view, options_.refine, &tag)) {
      // Raw corners of a modified copy are biased: no refinement, no tag.
      if (found.from_copy[t]) {
        ++local.unrefined_copy_tags;
        continue;
      }
      ++local.unrefined_tags;
    }
    ++local.tags;
    if (edge_fit && corner_squares_) {
      RefineXJunctions(view, std::min(1.0, GridOf(tag.id)->tag_spacing), &tag);
    }
    out.corners = tag.corners;
    fitted.push_back(out);
  }
  if (photometric && options_.predict_missing_tags) {
    std::set<int> tried;
    for (const FittedTag& tag : fitted) tried.insert(tag.id);
    PredictMissingTags(view, camera, std::move(tried), refused, &fitted, &local);
  }
  std::set<int> fitted_ids;
  for (const FittedTag& tag : fitted) fitted_ids.insert(tag.id);
  for (const auto& [id, failure] : refused) {
    if (fitted_ids.count(id) == 0) ++local.refused_tags[static_cast<int>(failure)];
  }
  std::vector<Observation> observations;
  for (const FittedTag& tag : fitted) {
    for (int k = 0; k < 4; ++k)
      observations.push_back({PointId(tag.id, k), tag.corners[k], tag.crlb_px[k]});
  }
  std::sort(observations.begin(), observations.end(),
            [](const Observation& a, const Observation& b) { return a.point_id < b.point_id; });
  if (counts) *counts = local;
  return observations;
}

void FrameDetector::PredictMissingTags(const GrayImageView& view, const CameraIntrinsics* camera,
                                       std::set<int> tried,
                                       const std::map<int, FitFailure>& refused,
                                       std::vector<FittedTag>* fitted,
                                       DetectionCounts* counts) const {
  std::vector<double> residuals;
  for (const FittedTag& tag : *fitted) residuals.push_back(tag.residual_rms_gray);
  if (residuals.empty()) return;
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  const double max_residual_gray =
      options_.max_predicted_residual_ratio * residuals[residuals.size() / 2];
  const bool lens = camera && camera->IsDistorted();
  // Through a wide lens the tags AprilTag 3 misses are the squeezed ones at the image circle's
  // edge, where fitted corners were measured to carry a bias that moves a calibration's lens
  // parameters by 3-7 std (tests/bench/calibrate_wide_rendered_test.cc, 190 deg eucm and double
  // sphere): no tag is predicted farther off the axis than a fitted decoded tag's corner, where
  // that is past a wide lens's kMinWideHalfFieldDeg (a narrower field has no such edge: on an
  // EuRoC-like lens the guard dropped a board's outer tags, 5 of 864).
  auto off_axis = [&](const Eigen::Vector2d& pixel) {
    Eigen::Vector3d ray;
    return UnprojectToRay(*camera, pixel, &ray) ? std::acos(ray.normalized().z()) : M_PI;
  };
  double max_off_axis = kMinWideHalfFieldDeg * M_PI / 180;
  if (lens) {
    for (const FittedTag& tag : *fitted)
      for (const Eigen::Vector2d& c : tag.corners)
        max_off_axis = std::max(max_off_axis, off_axis(c));
  }
  // Chebyshev distance in tags: a homography in pixels through a fisheye's bent edges holds over
  // one tag only.
  const int reach = !lens && options_.refine.curved_edges ? 1 : 2;
  constexpr int kMaxPasses = 3;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    int added = 0;
    for (const GridIds& g : grids_) {
      for (int index = 0; index < g.num_tags; ++index) {
        const int id = g.first_id + index;
        if (tried.count(id) > 0) continue;
        const int r = index / g.tag_cols, c = index % g.tag_cols;
        // The nearest fitted tags first (within one tag), then farther ones: the board's image
        // is a homography over a patch the smaller the more the lens bends it (measured on an
        // EuRoC-like lens, k1 = -0.28, fitted in pixels: 5 x 5 tags miss it by 0.5-0.76 px at
        // the image's edge, where 3 x 3 hold it).
        std::array<Eigen::Vector2d, 4> corners;
        bool predicted = false;
        for (int within = 1; within <= reach && !predicted; ++within) {
          std::vector<const FittedTag*> near;
          for (const FittedTag& tag : *fitted) {
            const int other = tag.id - g.first_id;
            if (other < 0 || other >= g.num_tags) continue;
            if (std::max(std::abs(other / g.tag_cols - r), std::abs(other % g.tag_cols - c)) <=
                within)
              near.push_back(&tag);
          }
          predicted = !near.empty() && PredictCorners(g, index, near, camera, &corners);
        }
        if (!predicted || NearBorder(corners, view)) continue;
        // Not past the field the decoded tags reach, unless AprilTag 3 decoded this one there and
        // its fit failed from a thrown-off corner (moved, not converged, diverged), not for the
        // reasons of a squeezed tag at the image circle's edge (border, contrast, pixels).
        const auto decoded = refused.find(id);
        const bool thrown_off =
            decoded != refused.end() && (decoded->second == FitFailure::kMoved ||
                                         decoded->second == FitFailure::kNotConverged ||
                                         decoded->second == FitFailure::kDiverged);
        if (lens && !thrown_off) {
          bool beyond = false;
          for (const Eigen::Vector2d& corner : corners) beyond |= off_axis(corner) > max_off_axis;
          if (beyond) continue;
        }
        tried.insert(id);
        const PhotometricFitResult fit = FitTagPhotometric(view, patterns_[PointId(id, 0) / 4],
                                                           corners, options_.photometric, camera);
        if (!fit.ok() || !(fit.residual_rms_gray <= max_residual_gray)) {
          // A decoded tag refused again is counted once, in refused_tags (RefineTags).
          if (decoded == refused.end()) ++counts->refused_predictions;
          continue;
        }
        fitted->push_back({id, fit.corners, fit.crlb_px, fit.residual_rms_gray});
        ++counts->tags;
        counts->covered_tags += fit.outlier_pixels > 0 ? 1 : 0;
        if (decoded != refused.end()) {
          ++counts->refitted_tags;
        } else {
          ++counts->predicted_tags;
        }
        ++added;
      }
    }
    if (added == 0) break;
  }
}

bool FrameDetector::PredictCorners(const GridIds& g, int index,
                                   const std::vector<const FittedTag*>& near,
                                   const CameraIntrinsics* camera,
                                   std::array<Eigen::Vector2d, 4>* corners) const {
  // A fit of the neighbours' corners worse than this: the image is not a homography of the board
  // over this patch (an unknown lens), and the prediction would not be one either.
  constexpr double kMaxNeighbourResidualPx = 0.5;
  std::vector<Eigen::Vector2d> on_board, seen;
  for (const FittedTag* tag : near) {
    for (int k = 0; k < 4; ++k) {
      on_board.push_back(g.corners_on_board[4 * (tag->id - g.first_id) + k]);
      seen.push_back(tag->corners[k]);
    }
  }
  PlaneToImage to_image;
  if (!to_image.Fit(camera, on_board, seen)) return false;
  for (size_t n = 0; n < on_board.size(); ++n) {
    Eigen::Vector2d pixel;
    if (!to_image(on_board[n], &pixel) || !((pixel - seen[n]).norm() <= kMaxNeighbourResidualPx))
      return false;
  }
  for (int k = 0; k < 4; ++k) {
    if (!to_image(g.corners_on_board[4 * index + k], &(*corners)[k])) return false;
  }
  return true;
}

}  // namespace calibench
