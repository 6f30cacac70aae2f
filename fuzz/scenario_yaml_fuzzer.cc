// libFuzzer target: scenario / entry-point YAML -> LoadRunConfigFromString.
//
// Contract checked on every input:
//   - the loader returns (true) or (false with a message), never crashes, hangs or leaks;
//   - a refusal comes with a message;
//   - an accepted configuration round-trips: ResolvedYaml(config) loads again, and resolving that
//     gives the same text (the resolved file is what `calibench run` records for --resume);
//   - a small accepted oracle scenario builds its scene and source, or refuses with a reason.
// Any violation calls __builtin_trap(), which libFuzzer reports as a crash.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "bench/config/config_io.h"
#include "fuzz/fuzz_check.h"

namespace {

void Check(bool ok, const char* what, const std::string& context = "") {
  calibench::FuzzRequire(ok, "scenario_yaml_fuzzer", what, context);
}

// Relative `base:` paths resolve next to this (non-existent) file, so inputs cannot reach the
// project's own configs by accident; absolute paths still reach the file system (read-only).
constexpr char kVirtualPath[] = "/nonexistent/fuzz/scenario.yaml";
// Scenarios whose measurement source is built per input (larger ones are only loaded).
constexpr double kMaxFrames = 2000;
constexpr size_t kMaxPoints = 1000;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string yaml(reinterpret_cast<const char*>(data), size);
  calibench::RunConfig config;
  std::string why;
  if (!calibench::LoadRunConfigFromString(yaml, kVirtualPath, &config, &why)) {
    Check(!why.empty(), "refused without a message", yaml);
    return 0;
  }
  const std::string resolved = calibench::ResolvedYaml(config);
  calibench::RunConfig reloaded;
  Check(calibench::LoadRunConfigFromString(resolved, kVirtualPath, &reloaded, &why),
        "the resolved configuration does not load again", why + "\n--- resolved:\n" + resolved);
  const std::string again = calibench::ResolvedYaml(reloaded);
  Check(again == resolved, "the resolved configuration changes on a second round trip",
        resolved + "\n--- resolved again:\n" + again);
  // An accepted oracle scenario builds its scene and measurement source (or says why not) without
  // crashing; kept to small ones so that each input stays fast.
  for (const calibench::ScenarioConfig& s : config.scenarios) {
    const double frames =
        s.duration_s * std::max(s.measurements.sample_rate_hz, s.measurements.eval_rate_hz);
    if (s.detections != calibench::Detections::kOracle || frames > kMaxFrames ||
        s.points.xyz.size() > kMaxPoints)
      continue;
    const calibench::SceneTruth scene = s.MakeScene();
    const auto source =
        calibench::OracleSource::Create(scene, s.OracleSourceOptions(), s.TrialSeedOf(0), &why);
    Check(source != nullptr || !why.empty(), "no source and no reason", resolved);
  }
  return 0;
}
