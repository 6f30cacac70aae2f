// From an image to target observations: AprilTag detection, corner refinement, and the matching
// of (tag id, corner index) to the points of a target made of AprilGrids.
//
// Point numbering (sim/target.h): the grids' corners are concatenated grid after grid; corner k
// (detector order: bottom-left, bottom-right, top-right, top-left) of the tag with id `id` on grid
// g is point offset(g) + 4 (id - g.first_id) + k. All grids must use one family and one border
// width (black_tag_border) and no id may appear on two grids (a detection could not be
// attributed), and either every grid has Kalibr's corner squares or none has.
// Pixels follow calibench's convention (camera.h: pixel centres at integers).
//
// Grids with corner squares (AprilGrid::corner_squares: black squares of edge tag_spacing x the
// tag's at every tag corner, touching it, so each tag corner is an X-junction):
//   1. Finding tags. In a sharp image AprilTag 3's segmentation joins each tag to its corner
//      squares and traces no tag outline (measured: 0 of 36 tags on the TUM VI frames, 32 of 36 on
//      EuRoC's). The tags the image does not give are looked for in a copy whose black is eroded by
//      one pixel (3 x 3 max filter: touching corners part by ~2 px). An edge with unit normal n
//      moves inward by |n_x| + |n_y| px under that filter (its support function), so each of the
//      tag's four edge lines is moved back out by that much and the corners re-intersected. Then
//      the squares next to the tags found are painted white (each mapped through the homography
//      of a found tag, grown by 1.5 px) and the detector runs again, up to 3 times, until no new
//      tag appears: the tags they joined stand alone (measured on rendered Kalibr grids: 81-84%
//      of tags found before, 99.4-100% after; tests/detect/kalibr_grid_test.cc). A fisheye without
//      a camera paints only the squares touching found tags (a homography extrapolates badly
//      through its bent edges); with a distorted `camera` (any lens family) the squares are
//      mapped through its lens (the homography on the tangent plane about the tag's centre ray,
//      detect/tangent_plane.h), up to two tags from a found tag. Tags found only in such copies
//      keep no unrefined corners.
//   2. Refining corners. kPhotometric fits the tag's pattern with its four squares. kEdgeFit
//      follows the edge fit by the saddle point of each X-junction (cv::cornerSubPix, window
//      (2 w + 1)^2 px, w = min(3, 0.4 x the square's edge in px), kept if it moves < 1 px):
//      symmetric about the corner, it is not biased by saturated white, which pulls the edge fit's
//      mean-level crossings towards the black (measured on EuRoC: 0.27 px inward;
//      docs/aprilgrid_frames.md).
//
// Predicted tags (predict_missing_tags, with kPhotometric). AprilTag 3 misses tags that are small
// or oblique at quad_decimate 2 (measured on the default rig, `calibench detect
// configs/rig.yaml --max-frames 100`: 2800 of 3730 tags in view decoded, most misses on its
// 45-degree grid at the sway's oblique phases; with the predictions 3608, their corners unbiased
// and at 1.3x their Cramer-Rao std as the decoded ones are). Once the decoded tags are fitted, each
// missing tag of a grid with a fitted tag within two tags of it (one for a fisheye without a
// camera) is predicted: the homography from the board plane to the image (to the tangent plane
// about the neighbours' mean ray through a distorted camera) fitted to the corners of the fitted
// tags within one tag of it, or when there are none or they do not fit, within two
// (detect/plane_to_image.h; the smaller patch holds where a lens bends the board's image), kept
// only if it fits them to 0.5 px (one neighbour's four corners fix it exactly: fitted corners at
// ~0.01 px extrapolate to a tag two pitches away within ~0.1 px), maps the tag's square to its
// four corners. The tag's pattern is fitted from there. The
// position names the tag (its neighbours are a pitch away, the fit moves a corner at most
// max_correction_px); the fit must explain the pixels: residual RMS at most
// max_predicted_residual_ratio x the decoded tags' median (an occluded or shadowed tag is refused
// and counted). Predicted tags join the neighbours of the next ones. A decoded tag whose fit from
// AprilTag 3's corners was refused (a corner thrown off, e.g. by a Kalibr corner square: measured
// on EuRoC-like rendered views, 3-6 of 864 tags) is predicted the same way, its id being known;
// when its fit failed from a thrown-off corner (moved, not converged, diverged) it is not held to
// the field the fitted tags reach (AprilTag 3 decoded it there).
//
// Perspective views (perspective_views_below_tags, with a wide `camera`). When AprilTag 3 decodes
// fewer than that many grid tags in an image (a board near a fisheye's image circle, its quads
// bent), the image is resampled into perspective views covering the lens's field
// (detect/perspective_views.h: straight edges again) and AprilTag 3 runs on each; a tag not yet
// found gets the image pixels of its corners through the views' rays, and is fitted from there as
// a tag found in a modified copy is (no unrefined corners kept). Measured on 20-view rendered
// 190 deg calibrations: the one view of 140 whose board AprilTag 3 missed is found.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "detect/apriltag_detector.h"
#include "detect/corner_refinement.h"
#include "detect/perspective_views.h"
#include "detect/photometric_fit.h"
#include "sim/render.h"
#include "sim/target.h"

namespace calibench {

struct SquareToPaint;  // corner_squares.cc.

// How a decoded tag's corners are refined.
enum class CornerRefinement {
  kNone,         // AprilTag 3's corners.
  kEdgeFit,      // Four straight (or curved) edges fitted by profiles (corner_refinement.h).
  kPhotometric,  // The tag's whole pattern fitted to its pixels (photometric_fit.h): a tag whose
                 // fit is refused is dropped, and counted by reason.
};
// "none", "edge_fit", "photometric"; false for another name.
bool ParseCornerRefinement(const std::string& name, CornerRefinement* refinement);
const char* CornerRefinementName(CornerRefinement refinement);

struct FrameDetectorOptions {
  AprilTagOptions detector;  // family and black_border_bits are taken from the grids.
  // kPhotometric by default. On grids with corner squares its model holds the squares too.
  CornerRefinement refinement = CornerRefinement::kPhotometric;
  CornerRefineOptions refine;  // The edge fit's; width_at_border is taken from the family.
  PhotometricFitOptions photometric;
  // The camera the images come from (a calibration, or its previous iteration): the photometric
  // fit is then drawn through its lens (lens-aware, photometric_fit.h), also for fisheye lenses,
  // whose edge fit otherwise takes curved edges. nullopt: a homography in pixels.
  std::optional<CameraIntrinsics> camera;
  // Tags with a corner closer than this to the image border are dropped: a tag cut by the border
  // still decodes, but its corners are extrapolated (measured: up to 2 px off).
  double min_border_distance_px = 2.0;
  // Tags of a grid that AprilTag 3 did not decode, or whose fit from its corners was refused, are
  // fitted where the tags fitted around them put them (kPhotometric only; "Predicted tags" above).
  bool predict_missing_tags = true;
  // A predicted tag is kept when its fit's residual RMS is at most this times the median of the
  // image's decoded tags' (the known pattern explains its pixels as well as theirs). >= 1.
  double max_predicted_residual_ratio = 2.0;
  // With a wide `camera` (a half-field of kMinWideHalfFieldDeg or more over the image): an image
  // in which AprilTag 3 decodes fewer usable grid tags than this is searched again in perspective
  // views through the camera ("Perspective views" above); 0: never (the default: a detector of
  // single-tag crops, or of frames whose boards are known to be whole, has no use for them). A
  // board near a 190 deg lens's image circle bends every tag's quad: none decodes, and without
  // one decoded tag no tag is predicted either. `calibrate --images` with a wide family uses 4.
  int perspective_views_below_tags = 0;
  bool Check(std::string* why) const;
};

struct Observation {
  int point_id = -1;
  Eigen::Vector2d pixel;
  // The corner's Cramer-Rao std per axis (px) from the photometric fit's Fisher information; NaN
  // for other refinements.
  double crlb_px = std::numeric_limits<double>::quiet_NaN();
};

struct DetectionCounts {
  int tags = 0;            // Tags detected and matched to a grid.
  int unknown_tags = 0;    // Detected ids that are on no grid.
  int unrefined_tags = 0;  // Tags whose edge fit was refused (raw corners kept).
  // Tags found only in a modified copy (corner squares: eroded, or squares painted out) whose edge
  // fit was refused: dropped, since such raw corners are biased.
  int unrefined_copy_tags = 0;
  // Tags whose photometric fit was refused (dropped), by FitFailure (photometric_fit.h); index 0
  // (kNone) stays 0.
  std::array<int, kNumFitFailures> refused_tags{};
  int RefusedTags() const {
    int n = 0;
    for (int v : refused_tags) n += v;
    return n;
  }
  int border_tags = 0;  // Tags dropped for touching the image border.
  // Of `tags`: not decoded, fitted where their neighbours predicted them (predict_missing_tags).
  int predicted_tags = 0;
  // Of `tags`: decoded, but refused by the photometric fit from AprilTag 3's corners (a corner
  // thrown off by a corner square, say) and then fitted where their neighbours put them
  // (predict_missing_tags; not in refused_tags).
  int refitted_tags = 0;
  // Of `tags`: fitted without pixels that disagree with their pattern (covered in part: a finger,
  // another board; PhotometricFitResult::outlier_pixels > 0).
  int covered_tags = 0;
  // Predicted tags whose fit was refused or explained the pixels worse than the decoded tags'
  // (dropped; not in refused_tags, as nothing was detected there).
  int refused_predictions = 0;
  // Detections of an id found more than once in the image (a false positive, or a tag printed
  // twice): all dropped, since which one is the grid's is unknown.
  int duplicate_tags = 0;
};

// The tags of one image before their corners are refined: what AprilTag 3 (and, on grids with
// corner squares, the search among them) found, matched to the grids, with the drops counted.
// Keeping it lets a calibration re-fit the corners through each new estimate of its camera
// without detecting again.
struct FoundTags {
  std::vector<TagDetection> tags;  // Matched to a grid, one per id, away from the image border.
  // Per tag: its corners come from a modified copy of the image (eroded, squares painted out).
  std::vector<bool> from_copy;
  DetectionCounts counts;  // unknown_tags, duplicate_tags and border_tags.
};

class FrameDetector {
 public:
  // nullptr (and *why) for invalid options, no grids, mixed families or an id on two grids.
  static std::unique_ptr<FrameDetector> Create(const std::vector<AprilGrid>& grids,
                                               const FrameDetectorOptions& options,
                                               std::string* why);
  int NumPoints() const { return num_points_; }
  // Point id of corner k of tag `id`, or -1 when no grid has the id.
  int PointId(int id, int corner) const;
  // Observations of the image sorted by point id. Not thread-safe (one per thread).
  std::vector<Observation> Detect(const GrayImage& image, DetectionCounts* counts) const;
  // The same on a raw 8-bit buffer with a row stride in bytes (e.g. a cv::Mat, zero copy).
  std::vector<Observation> Detect(const uint8_t* pixels, int width, int height, int stride,
                                  DetectionCounts* counts) const;
  // Detect in two steps: the tags, then their corners refined (`camera`: the lens the photometric
  // fit is drawn through, nullptr for a homography in pixels; Detect passes options.camera).
  // RefineTags' counts add the refinement's to found.counts.
  FoundTags FindTags(const GrayImageView& image) const;
  std::vector<Observation> RefineTags(const GrayImageView& image, const FoundTags& found,
                                      const CameraIntrinsics* camera,
                                      DetectionCounts* counts) const;
  // Whether FindTags depends on options.camera: corner squares are painted out through a lens that
  // distorts, or perspective views may be searched through it.
  bool FindingUsesCamera() const {
    return (corner_squares_ && SquareLens() != nullptr) ||
           (options_.camera && options_.perspective_views_below_tags > 0);
  }

 private:
  FrameDetector() = default;
  struct GridIds {
    int first_id, num_tags, first_point;
    int tag_rows, tag_cols;
    double tag_spacing;  // The corner squares' edge / the tag's.
    // AprilGrid::CornersInBoard's (x, y) (m), in point order: corner k of tag i at 4 i + k.
    std::vector<Eigen::Vector2d> corners_on_board;
  };
  const GridIds* GridOf(int id) const;  // The grid holding tag `id`, or nullptr.
  // The lens the corner squares are painted through: options_.camera when it distorts, else
  // nullptr (a homography in pixels).
  const CameraIntrinsics* SquareLens() const;
  // How the squares next to a found tag are mapped into an image: through `lens` (the homography
  // on the tangent plane about the tag's ray), else by a homography in pixels, which extrapolates
  // badly when the image's edges are curved (a fisheye without a camera).
  struct SquareMapping {
    const CameraIntrinsics* lens = nullptr;
    bool curved_edges = false;
  };
  // Adds the tags that corner squares hide (header comment): *from_copy grows with *tags.
  void FindTagsAmongSquares(const GrayImageView& view, const SquareMapping& mapping,
                            std::vector<TagDetection>* tags, std::vector<bool>* from_copy) const;
  // The grid tags of `tags` that FindTags keeps: grid ids decoded once, away from the border (the
  // others counted in FoundTags::counts).
  FoundTags UsableTags(const GrayImageView& view, const std::vector<TagDetection>& tags,
                       const std::vector<bool>& from_copy) const;
  // Adds the grid tags found in perspective views_ (header comment) whose ids *tags lacks.
  void FindTagsInPerspectiveViews(const GrayImageView& view, std::vector<TagDetection>* tags,
                                  std::vector<bool>* from_copy) const;
  // The corner squares to paint out next to the tags found (corner_squares.cc).
  std::vector<SquareToPaint> SquaresNear(const std::vector<TagDetection>& tags,
                                         const SquareMapping& mapping) const;
  // A tag whose corners were fitted: decoded, or predicted.
  struct FittedTag {
    int id;
    std::array<Eigen::Vector2d, 4> corners;
    std::array<double, 4> crlb_px;
    double residual_rms_gray;  // The photometric fit's; NaN for other refinements.
  };
  // Fits the grid tags missing from *fitted where their fitted neighbours put them (header
  // comment); `tried`: ids not to predict (fitted). `refused`: decoded ids whose fit was refused,
  // with its reason (RefineTags counts those not fitted again in counts->refused_tags). Appends
  // the kept ones, counts in *counts.
  void PredictMissingTags(const GrayImageView& view, const CameraIntrinsics* camera,
                          std::set<int> tried, const std::map<int, FitFailure>& refused,
                          std::vector<FittedTag>* fitted, DetectionCounts* counts) const;
  // The four corners (detector order) of tag `index` of grid g from the fitted tags `near` of the
  // same grid; false when their homography does not fit them or the tag does not project.
  bool PredictCorners(const GridIds& g, int index, const std::vector<const FittedTag*>& near,
                      const CameraIntrinsics* camera,
                      std::array<Eigen::Vector2d, 4>* corners) const;
  bool NearBorder(const std::array<Eigen::Vector2d, 4>& corners, const GrayImageView& view) const;
  bool corner_squares_ = false;
  std::vector<GridIds> grids_;
  int num_points_ = 0;
  FrameDetectorOptions options_;
  std::shared_ptr<const TagFamily> family_;
  std::vector<TagPattern> patterns_;  // Per tag (point id / 4): the photometric fit's model.
  // The perspective views covering the camera's field for images of views_size_ (computed by
  // the first FindTags that needs them; a detector serves one thread, as Detect says).
  mutable std::vector<PerspectiveView> views_;
  mutable std::array<int, 2> views_size_{-1, -1};
  std::unique_ptr<AprilTagDetector> detector_;
};

}  // namespace calibench
