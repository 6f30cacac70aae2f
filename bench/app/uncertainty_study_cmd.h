// `calibench uncertainty-study`: the Monte Carlo validation of the projection uncertainty
// (metrics/projection_uncertainty_study.h) over lens families, view counts and distances, as the
// Markdown table of docs/results/uncertainty.md.
#pragma once

#include <string>

namespace calibench {

struct UncertaintyStudyArgs {
  std::string out_path;  // Markdown, written atomically; empty: stdout only.
  int draws = 100;       // Re-solves per case.
};

// 0 on success; 2 for bad arguments; 3 when the output cannot be written; 4 when a case failed.
int UncertaintyStudy(const UncertaintyStudyArgs& args);

}  // namespace calibench
