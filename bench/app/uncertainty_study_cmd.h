// `calibench uncertainty-study`: the Monte Carlo validation of the projection uncertainty
// (metrics/projection_uncertainty_study.h) over lens families, view counts and distances, as the
// Markdown table of docs/results/uncertainty.md; with `rendered`, also on corners detected in
// rendered checkerboard images (sim/checkerboard_image.h, detect/chessboard.h): every draw renders
// the same views with new image noise and re-detects them, and the prediction uses the detector's
// corner error measured over those draws.
#pragma once

#include <string>

namespace calibench {

struct UncertaintyStudyArgs {
  std::string out_path;   // Markdown, written atomically; empty: stdout only.
  int draws = 100;        // Re-solves per case.
  bool rendered = false;  // Also the rendered cases (each draw renders and detects every view).
  int threads = 0;        // Rendering and detection in parallel; 0: all cores.
};

// 0 on success; 2 for bad arguments; 3 when the output cannot be written; 4 when a case failed.
int UncertaintyStudy(const UncertaintyStudyArgs& args);

}  // namespace calibench
