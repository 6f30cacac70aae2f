#include "bench/app/corner_bias_cmd.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>

#include "bench/run/csv.h"
#include "detect/corner_bias.h"
#include "util/format.h"
#include "util/parallel_for.h"

namespace calibench {

namespace {

// corner_bias.csv's header (docs/outputs.md).
std::string CornerBiasHeader() {
  return CsvLine({"case",
                  "lens",
                  "black_border_bits",
                  "corner_squares",
                  "tag_px",
                  "tag_edge_px",
                  "tilt_deg",
                  "roll_deg",
                  "view_angle_deg",
                  "blur_sigma_px",
                  "centre_u_px",
                  "centre_v_px",
                  "stage",
                  "corner",
                  "bias_u_px",
                  "bias_v_px",
                  "bias_radial_px",
                  "bias_tangent_px",
                  "view_rms_px",
                  "noise_rms_px",
                  "rms_px",
                  "crlb_px",
                  "rms_over_crlb",
                  "detections",
                  "failed",
                  "refused",
                  "black_area_px2",
                  "rendered_black_area_px2",
                  "wall_per_tag_us",
                  "status"});
}

// The row of case i's corner k at detector stage `stage`.
std::string CornerBiasLine(const CornerBiasCase& c, const CornerBiasResult& r, int stage, int k,
                           size_t i) {
  auto num = [](double v) { return FormatNumber(v, 10); };
  const CornerStageResult& s = r.stages[stage];
  const CornerStats& cs = s.corners[k];
  return CsvLine({std::to_string(i),
                  CornerBiasLensName(c.lens),
                  std::to_string(c.black_border_bits),
                  c.corner_squares ? "1" : "0",
                  num(c.tag_px),
                  num(r.tag_edge_px),
                  num(c.tilt_deg),
                  num(c.roll_deg),
                  num(r.view_angle_deg),
                  num(c.blur_sigma_px),
                  num(r.centre_px.x()),
                  num(r.centre_px.y()),
                  CornerStageName(static_cast<CornerStage>(stage), c.corner_squares),
                  std::to_string(k),
                  num(cs.bias.x()),
                  num(cs.bias.y()),
                  num(cs.radial_px),
                  num(cs.tangent_px),
                  num(cs.view_rms_px),
                  num(cs.noise_rms_px),
                  num(s.rms_px),
                  num(r.crlb_px),
                  num(s.rms_px / r.crlb_px),
                  std::to_string(s.detections),
                  std::to_string(s.failed),
                  FormatFitFailures(s.refused),
                  num(r.black_area_px2),
                  num(r.rendered_black_area_px2),
                  num(s.us_per_tag),
                  r.ok ? "ok" : r.message});
}

}  // namespace

int CornerBias(const CornerBiasArgs& args) {
  CornerBiasOptions options;
  options.draws = args.draws;
  options.views = args.views;
  options.supersample = args.supersample;
  std::string why;
  if (!options.Check(&why) || args.threads < 1) {
    std::cerr << "calibench: corner-bias: " << (why.empty() ? "--threads must be >= 1" : why)
              << "\n";
    return 2;
  }
  const std::vector<CornerBiasCase> cases = DefaultCornerBiasCases();
  std::vector<CornerBiasResult> results(cases.size());
  ParallelFor(cases.size(), args.threads, [&](int /*worker*/, size_t i) {
    results[i] = MeasureCornerBias(cases[i], static_cast<int>(i), options);
  });
  std::string csv = CornerBiasHeader();
  // The largest |radial bias| of a corner: edge fit, and the photometric fit that fits the case
  // (lens-aware with a lens).
  double worst_edge = 0, worst_photometric = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const CornerBiasCase& c = cases[i];
    const CornerBiasResult& r = results[i];
    for (int st = 0; st < kNumCornerStages; ++st) {
      const CornerStage stage = static_cast<CornerStage>(st);
      const CornerStageResult& s = r.stages[st];
      if (!s.run && r.ok) continue;
      for (int k = 0; k < 4; ++k) {
        const CornerStats& cs = s.corners[k];
        csv += CornerBiasLine(c, r, st, k, i);
        if (!r.ok || !std::isfinite(cs.radial_px)) continue;
        if (stage == CornerStage::kEdgeFit)
          worst_edge = std::max(worst_edge, std::abs(cs.radial_px));
        const bool best_photometric = c.lens == CornerBiasLens::kNone
                                          ? stage == CornerStage::kPhotometric
                                          : stage == CornerStage::kLensAware;
        if (best_photometric)
          worst_photometric = std::max(worst_photometric, std::abs(cs.radial_px));
      }
    }
  }
  if (!WriteFileAtomically(args.out_path, csv, &why)) {
    std::cerr << "calibench: corner-bias: " << why << "\n";
    return 3;
  }
  std::fprintf(
      stderr,
      "calibench: corner-bias: %zu cases x %d views x %d draws -> %s (largest |radial bias| "
      "of a corner: edge fit %.4f px, photometric fit (lens-aware with a lens) %.4f px)\n",
      cases.size(), options.views, options.draws, args.out_path.c_str(), worst_edge,
      worst_photometric);
  return 0;
}

}  // namespace calibench
