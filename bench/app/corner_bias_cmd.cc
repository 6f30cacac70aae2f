#include "bench/app/corner_bias_cmd.h"

#include <atomic>
#include <cstdio>
#include <iostream>
#include <thread>
#include <vector>

#include "bench/run/csv.h"
#include "core/format.h"
#include "detect/corner_bias.h"

namespace calibench {

int CornerBias(const CornerBiasArgs& args) {
  CornerBiasOptions options;
  options.draws = args.draws;
  options.views = args.views;
  std::string why;
  if (!options.Check(&why) || args.threads < 1) {
    std::cerr << "calibench: corner-bias: " << (why.empty() ? "--threads must be >= 1" : why)
              << "\n";
    return 2;
  }
  const std::vector<CornerBiasCase> cases = DefaultCornerBiasCases();
  std::vector<CornerBiasResult> results(cases.size());
  std::atomic<size_t> next{0};
  std::vector<std::thread> workers;
  workers.reserve(args.threads);
  for (int t = 0; t < args.threads; ++t) {
    workers.emplace_back([&] {
      for (size_t i = next++; i < cases.size(); i = next++)
        results[i] = MeasureCornerBias(cases[i], static_cast<int>(i), options);
    });
  }
  for (std::thread& w : workers) w.join();
  auto num = [](double v) { return FormatNumber(v, 10); };
  std::string csv = CsvLine({"case",
                             "tag_px",
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
                             "detections",
                             "black_area_px2",
                             "rendered_black_area_px2",
                             "crlb_px",
                             "fitted_blur_px",
                             "refused",
                             "us_per_tag",
                             "status"});
  double worst_refined = 0, worst_photometric = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const CornerBiasCase& c = cases[i];
    const CornerBiasResult& r = results[i];
    const std::string refused = FormatFitFailures(r.photometric_failures);
    for (const std::string stage : {"raw", "refined", "photometric"}) {
      const bool photometric = stage == "photometric";
      const auto& stats = stage == "raw" ? r.raw : photometric ? r.photometric : r.refined;
      const int detections = photometric ? r.photometric_draws : r.detected_draws;
      const double us = stage == "raw" ? r.detect_us : photometric ? r.photometric_us : r.refine_us;
      for (int k = 0; k < 4; ++k) {
        const CornerStats& s = stats[k];
        csv += CsvLine({std::to_string(i),
                        num(c.tag_px),
                        num(c.tilt_deg),
                        num(c.roll_deg),
                        num(r.view_angle_deg),
                        num(c.blur_sigma_px),
                        num(c.centre_px.x()),
                        num(c.centre_px.y()),
                        stage,
                        std::to_string(k),
                        num(s.bias.x()),
                        num(s.bias.y()),
                        num(s.radial_px),
                        num(s.tangent_px),
                        num(s.view_rms_px),
                        num(s.noise_rms_px),
                        std::to_string(detections),
                        num(r.black_area_px2),
                        num(r.rendered_black_area_px2),
                        photometric ? num(r.photometric_crlb_px) : "",
                        photometric ? num(r.photometric_blur_px) : "",
                        photometric ? refused : "",
                        num(us),
                        r.ok ? "ok" : r.message});
        if (r.ok && stage == "refined")
          worst_refined = std::max(worst_refined, std::abs(s.radial_px));
        if (r.ok && photometric)
          worst_photometric = std::max(worst_photometric, std::abs(s.radial_px));
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
      "of a corner: edge fit %.4f px, photometric fit %.4f px)\n",
      cases.size(), options.views, options.draws, args.out_path.c_str(), worst_refined,
      worst_photometric);
  return 0;
}

}  // namespace calibench
