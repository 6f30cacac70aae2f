// Sub-pixel refinement of AprilTag corners by fitting the four edges of the black reference square
// (cv::cornerSubPix assumes X-junctions and was measured to make these L-corners worse).
//
// For each edge between detected corners k and k+1: at `samples_per_edge` points along the middle
// of the segment (a `corner_margin` fraction kept clear of each corner), read the intensity profile
// along the outward normal (bilinear interpolation, step 0.05 px) over +-h px, h = min(3 px,
// 0.45 of a tag cell). The dark level is the profile's inner end, the bright level its outer end;
// the edge point is where the profile first crosses their mean (linear interpolation): for an
// area-sampled step edge the profile is symmetric about the edge, so the crossing is unbiased.
// A total-least-squares line is fitted to each edge's points; corner k is the intersection of the
// lines of edges (k-1, k) and (k, k+1). Straight edges assume little distortion across one tag.
//
// curved_edges (for fisheye lenses, which bend a tag's edges: on rendered equidistant frames the
// straight fit shrank the focal length by 0.24% at 40 px tags): each edge is fitted as a parabola
// in the frame of its line, s(t) = a + b t + c t^2 (t along the TLS line from the points' mean, s
// across), and corner k is the intersection of the two curves, by Newton's method from the lines'
// intersection.
#pragma once

#include <string>

#include "detect/apriltag_detector.h"
#include "sim/render.h"

namespace calibench {

struct CornerRefineOptions {
  int samples_per_edge = 24;
  double corner_margin = 0.15;  // Fraction of the edge kept clear of each corner.
  double max_search_px = 3.0;   // Upper bound on h.
  double max_correction_px =
      1.0;                    // A refined corner farther than this from the raw one is refused.
  int width_at_border = 8;    // The family's reference square in cells (tag36h11: 8).
  bool curved_edges = false;  // Parabolic edges (see the header comment); lines if false.
  bool Check(std::string* why) const;
};

// Refines the corners of `detection` in place. Returns false (corners unchanged) when an edge has
// too few valid profile crossings, lines are parallel, or a correction exceeds max_correction_px.
bool RefineTagCorners(const GrayImageView& image, const CornerRefineOptions& options,
                      TagDetection* detection);

}  // namespace calibench
