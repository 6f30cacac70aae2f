// Reading and writing scenario YAML. The config I/O files (bench/config/config_*.cc) are the only
// ones that include yaml-cpp.
//
// The format is declared once, field by field, in bench/config/scenario_fields.cc and
// source_fields.cc (fields.h: each
// field's YAML key, member, type, default, unit, doc and check); method options in each type's
// VisitOptions (methods/method.h). The parser, the writer (ResolvedYaml), equality, the
// "did you mean" key lists and the reference (`calibench config-reference`, the generated part of
// docs/configuration.md) all come from those declarations: read them, not a copy here.
//
// File shapes (hand-written grammar, config_io.cc and config_sweep.cc):
//   base: ../common.yaml   # optional: load that scenario file first, then override it
//   scenario: {...}        # the scenario's fields (declared in scenario_fields.cc)
//   sweep: [{field, values: [...]} | {field, range: {from, to, step | log_step}}, ...]
// or an entry point `scenarios: [path | {inline scenario}, ...]`, optionally with
//   variants: [{suffix, note, of: [scenario names], scenario: {override}}, ...]
// (each named scenario again as NAME-SUFFIX with the override on top). `points`, `motion` and
// `reference` replace a base's section as a whole; a `methods:` list replaces the instances, a map
// updates them (config_methods.cc); a sweep axis `methods.NAME.field` changes one instance. Unknown
// keys, wrong types and invalid values are errors of the form "FILE:LINE:COL: FIELD: REASON".
#pragma once

#include <string>
#include <vector>

#include "bench/config/scenario.h"

namespace calibench {

struct RunConfig {
  std::vector<ScenarioConfig> scenarios;
  // Whether a scenario has a camera rig (`rig:`): its run's files have a camera column and rig.csv.
  bool HasRig() const {
    for (const ScenarioConfig& s : scenarios)
      if (s.rig.Any()) return true;
    return false;
  }
};

// Loads a scenario file or an entry point. On failure returns false and *why says file, line,
// column, field and reason.
bool LoadRunConfig(const std::string& path, RunConfig* config, std::string* why);
// Same, from YAML text (`virtual_path` names it in messages and anchors relative paths).
bool LoadRunConfigFromString(const std::string& yaml, const std::string& virtual_path,
                             RunConfig* config, std::string* why);

// The configuration with every default filled in, as an entry point with inline scenarios that
// LoadRunConfig reads back to the same values.
std::string ResolvedYaml(const RunConfig& config);

}  // namespace calibench
