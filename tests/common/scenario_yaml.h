// A valid minimal scenario as YAML text, for tests that splice one faulty line into it:
//   1 scenario:            4.. `extra` lines            6 (+extra) R_C, 7 x_C (`truth_lines`)
//   2   name: t            4 (+extra) truth:            8 (+extra) points: `points`
//   3   duration_s: 10     5 (+extra) intrinsics (thesis camera 1 with phi = 88 deg)
#pragma once

#include <string>

namespace calibench {

struct ScenarioYamlParts {
  std::string extra;
  std::string points = "{preset: thesis, count: 10}";
  std::string truth_lines = "    R_C: [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]\n    x_C: [0, -2, 0.5]\n";
};

inline std::string MinimalScenarioYaml(const ScenarioYamlParts& parts) {
  return "scenario:\n"
         "  name: t\n"
         "  duration_s: 10\n" +
         parts.extra +
         "  truth:\n"
         "    intrinsics: {fku_px: 800, fkv_px: 810, phi_deg: 88, u0_px: 320, v0_px: 240}\n" +
         parts.truth_lines + "  points: " + parts.points + "\n";
}

}  // namespace calibench
