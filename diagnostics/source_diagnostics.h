// Study-only measurement-source decorators, configured by a scenario's `diagnostics:` section:
// they change what a source reports so that a study can tell where an error comes from. The
// production sources (sim/measurements.h OracleSource, detect/rendered_source.h RenderedSource)
// know none of them.
//
//   corner error (a held source whose frames name their points, e.g. `detections: rendered`):
//     every measured pixel p of scene point i at frame time t is reported at its exact projection
//     x_i(t) (the scene's truth) plus a part of its error e = p - x_i(t):
//       1. e is shortened to at most corner_error_clip_px (0: the pipeline's selection of tags
//          and frames with no corner error; 0.3: only the outliers removed);
//       2. corner_error_part keeps all of e, its image x or y component, the mean e of its tag's
//          corners (kTagTranslation: the tag displaced, not deformed) or e minus that mean
//          (kTagShape); tags own 4 consecutive point ids (sim/target.h);
//       3. with corner_error_grid = g >= 0 only grid g's corners keep their error.
//   tag radial bias (any source of AprilGrid points, 4 consecutive points a tag): every corner
//     moves tag_radial_bias_px along its tag's diagonal, outward from the tag's projected centre
//     (where the exact projected diagonals cross); negative: inward. The direction comes from the
//     exact projections, so it adds to whatever noise the source drew.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sim/measurements.h"
#include "sim/scene.h"
#include "sim/target.h"

namespace calibench {

// The part of a detected corner's error that the corner-error diagnostic keeps (above).
enum class CornerErrorPart { kAll, kX, kY, kTagTranslation, kTagShape };
// "all", "x", "y", "tag_translation", "tag_shape"; false for another name.
bool ParseCornerErrorPart(const std::string& name, CornerErrorPart* part);
std::string CornerErrorPartName(CornerErrorPart part);
std::string CornerErrorPartNames();  // The accepted names, comma-separated.

struct DiagnosticsOptions {
  // Infinity (default): the measured corners' errors are kept whole.
  double corner_error_clip_px = std::numeric_limits<double>::infinity();
  CornerErrorPart corner_error_part = CornerErrorPart::kAll;
  int corner_error_grid = -1;       // -1: every grid.
  double tag_radial_bias_px = 0.0;  // px along each tag's diagonal; 0: none.
  bool CornerErrorActive() const {
    return corner_error_clip_px != std::numeric_limits<double>::infinity() ||
           corner_error_part != CornerErrorPart::kAll || corner_error_grid >= 0;
  }
  bool Active() const { return CornerErrorActive() || tag_radial_bias_px != 0; }
  bool Check(std::string* why) const;
};

// `source` wrapped in the decorators `options` asks for (the source itself when none). `scene`:
// the truth the source measures; `grids`: the AprilGrids whose corners its points are (their
// order and numbering: sim/target.h). Null (and *why) when a decorator cannot apply: the corner
// error needs a source held within segments whose frames name their points, and a grid index that
// exists.
std::unique_ptr<MeasurementSource> ApplyDiagnostics(std::unique_ptr<MeasurementSource> source,
                                                    const SceneTruth& scene,
                                                    const std::vector<AprilGrid>& grids,
                                                    const DiagnosticsOptions& options,
                                                    std::string* why);

// The tag radial bias applied to pixels `exact` (4 consecutive points a tag): the move of each.
// A degenerate (collapsed) tag does not move.
std::vector<Eigen::Vector2d> TagRadialMoves(double bias_px,
                                            const std::vector<Eigen::Vector2d>& exact);

}  // namespace calibench
