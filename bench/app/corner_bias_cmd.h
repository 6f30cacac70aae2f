// `calibench corner-bias`: the corner-error study of detect/corner_bias.h over its default cases,
// written as one CSV row per (case, corner, detector stage) and summarised on stderr.
#pragma once

#include <string>

namespace calibench {

struct CornerBiasArgs {
  std::string out_path;  // CSV, written atomically.
  int views = 8;         // Sub-pixel shifted views per case.
  int draws = 8;         // Noise draws per view.
  int supersample = 16;  // Renderer samples per pixel side at a board's outline (RenderOptions).
  int threads = 2;
};

// 0 on success; 2 with a message for bad arguments; 3 when the output cannot be written.
int CornerBias(const CornerBiasArgs& args);

}  // namespace calibench
