// The declarations (fields.h) of how the methods' measurements are made: the oracle's noise, the
// renderer and detector of rendered frames, and the study-only diagnostics. The rest of the
// scenario format is declared in scenario_fields.cc; the same visitors derive the parser, the
// writer, equality and docs/configuration.md from both.
#include <string>
#include <vector>

#include "bench/config/scenario.h"

namespace calibench {
namespace {

const EnumNames<CornerRefinement>& RefinementNames() {
  static const EnumNames<CornerRefinement> names{{{CornerRefinement::kPhotometric, "photometric"},
                                                  {CornerRefinement::kEdgeFit, "edge_fit"},
                                                  {CornerRefinement::kNone, "none"}},
                                                 "refinement"};
  return names;
}

const EnumNames<CornerErrorPart>& CornerErrorParts() {
  using P = CornerErrorPart;
  static const EnumNames<P> names = [] {
    EnumNames<P> n;
    n.noun = "part";
    for (P p : {P::kAll, P::kX, P::kY, P::kTagTranslation, P::kTagShape}) {
      static std::vector<std::string> storage;  // Names outlive the table.
      storage.reserve(8);
      storage.push_back(CornerErrorPartName(p));
      n.entries.emplace_back(p, storage.back().c_str());
    }
    return n;
  }();
  return names;
}

}  // namespace

void Visit(FieldVisitor& v, NoiseOptions& n) {
  v.Field({"point_sigma_m", "m", "Std of the Gaussian added to each point coordinate.", "≥ 0"},
          &n.point_sigma_m);
  v.Field({"pixel_sigma_px", "px", "Std of the Gaussian added to u and v.", "≥ 0"},
          &n.pixel_sigma_px);
  v.Field({"hold_s", "s", "Continuous sources: each draw is held this long."}, &n.hold_s);
  v.Field({"hold_frames", "frames",
           "Sampled sources: one draw per this many frames; 0: one draw for the whole run.", "≥ 0"},
          &n.hold_frames);
  v.Field({"outlier_fraction", "",
           "Probability that a pixel measurement is a gross outlier (held like the noise).",
           "in [0, 1]"},
          &n.outlier_fraction);
  v.Field({"outlier_sigma_px", "px", "Std of an outlier's further displacement, per axis.", "> 0"},
          &n.outlier_sigma_px);
  v.Check(nullptr, [&n](std::string* why) { return n.Check(why); });
}

void Visit(FieldVisitor& v, RenderedSourceOptions& o) {
  RenderOptions& ro = o.render;
  v.Field({"supersample", "samples",
           "n×n samples in pixels where two boards or a board's outline meet (pixels on one board "
           "hold exact cell areas)."},
          &ro.supersample);
  v.Field({"blur_sigma_px", "px", "Gaussian PSF; 0: none.", "≥ 0"}, &ro.blur_sigma_px);
  v.Field({"blur_grid", "",
           "The blur is computed on a grid this many times finer than the pixels; 0: automatic "
           "(ceil(3/σ), at most 8); 1: blur the pixels."},
          &ro.blur_grid);
  v.Field(
      {"noise_sigma_gray", "gray levels", "Gaussian image noise before 8-bit quantisation.", "≥ 0"},
      &ro.noise_sigma_gray);
  v.Field({"background_gray", "gray levels", "Background level."}, &ro.background_gray);
  v.Field({"black_gray", "gray levels", "Level of the tags' black."}, &ro.black_gray);
  v.Field({"white_gray", "gray levels", "Level of the tags' white."}, &ro.white_gray);
  v.Field({"threads", "", "Frames produced in parallel; 0: all cores. Results do not depend on it.",
           "≥ 0",
           [](double n, std::string* why) {
             return n >= 0 || (*why = "must be >= 0 (0: all cores)", false);
           }},
          &o.threads);
  VisitEnum(v, {"corner_refinement", "", "Sub-pixel corner refinement after AprilTag 3."},
            &o.detection.refinement, RefinementNames());
  v.Field(
      {"min_border_distance_px", "px", "Tags closer to the image border are dropped (counted)."},
      &o.detection.min_border_distance_px);
  v.Field({"predict_missing_tags", "",
           "Grid tags AprilTag 3 did not decode are fitted where their fitted neighbours put them "
           "(photometric refinement)."},
          &o.detection.predict_missing_tags);
  v.Field({"max_predicted_residual_ratio", "",
           "A predicted tag is kept when its fit's residual RMS is at most this times the median "
           "of the decoded tags'.",
           "≥ 1"},
          &o.detection.max_predicted_residual_ratio);
  v.Field(
      {"perspective_views_below_tags", "",
       "Through a wide lens (half field ≥ 60°) whose camera the detector is given (the unified, "
       "eucm and double-sphere truths): a frame in which AprilTag 3 decodes fewer grid tags is "
       "searched again in perspective views of the lens's field; 0: never (the default).",
       "≥ 0"},
      &o.detection.perspective_views_below_tags);
  VisitSection(v, {"detector", "", "AprilTag 3 options."}, &o.detection.detector, /*flow=*/true);
  v.Check(nullptr, [&o](std::string* why) { return o.render.Check(why); });
  v.Check(nullptr, [&o](std::string* why) { return o.detection.Check(why); });
}

void Visit(FieldVisitor& v, DiagnosticsOptions& d) {
  v.Field({"corner_error_clip_px", "px",
           "Each measured corner is reported at its exact projection plus its error "
           "shortened to this length (0: exact corners of the same detections; rendered).",
           "≥ 0",
           [](double x, std::string* why) {
             return x >= 0 ||
                    (*why = "must be >= 0 (.inf, the default: the detected corners)", false);
           }},
          &d.corner_error_clip_px);
  VisitEnum(v,
            {"corner_error_part", "",
             "Which part of each corner's error is kept (x/y component, its tag's "
             "mean error, or the rest)."},
            &d.corner_error_part, CornerErrorParts());
  v.Field({"corner_error_grid", "", "Only this grid's corners keep their errors; -1: every grid.",
           "≥ -1",
           [](double g, std::string* why) {
             return g >= -1 ||
                    (*why = "must be a grid's index (0, 1, ...) or -1 (every grid)", false);
           }},
          &d.corner_error_grid);
  v.Field({"tag_radial_bias_px", "px",
           "Every AprilGrid corner moves this far along its tag's diagonal, outward from the "
           "tag's exact projected centre (negative: inward), on top of the source's noise."},
          &d.tag_radial_bias_px);
  v.Check(nullptr, [&d](std::string* why) { return d.Check(why); });
}

void Visit(FieldVisitor& v, AprilTagOptions& a) {
  v.Field({"quad_decimate", "", "Image decimation for quad detection (1: full resolution)."},
          &a.quad_decimate);
  v.Field({"quad_sigma", "px", "Gaussian blur before quad detection."}, &a.quad_sigma);
  v.Field({"refine_edges", "", "AprilTag's own edge refinement."}, &a.refine_edges);
  v.Field({"decode_sharpening", "", "AprilTag's decode sharpening."}, &a.decode_sharpening);
  v.Field({"threads", "", "AprilTag's threads."}, &a.threads);
  v.Field({"max_hamming", "bits", "Bits corrected at most (2 raises false positives)."},
          &a.max_hamming);
  v.Check(nullptr, [&a](std::string* why) { return a.Check(why); });
}

}  // namespace calibench
