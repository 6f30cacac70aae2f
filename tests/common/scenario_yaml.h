// A valid minimal scenario as YAML text, for tests that splice one faulty line into it:
//   1 scenario:            4.. `extra` lines            6 (+extra) R_C, 7 x_C (`truth_lines`)
//   2   name: t            4 (+extra) truth:            8 (+extra) points: `points`
//   3   duration_s: 10     5 (+extra) intrinsics (thesis camera 1 with phi = 88 deg)
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bench/config/scenario.h"
#include "methods/options.h"

namespace calibench {

// Option `key` of instance `name` as text (as methods/options.h's key writes it: "1000"); "" when
// there is no such instance or option.
inline std::string MethodOption(const ScenarioConfig& s, const std::string& name,
                                const std::string& key) {
  const MethodInstance* m = s.FindMethod(name);
  if (m == nullptr) return "";
  const std::string text = OptionsKey(*m->method);
  const size_t at = text.find(key + "=");
  if (at == std::string::npos || (at > 0 && text[at - 1] != ';')) return "";
  const size_t start = at + key.size() + 1;
  return text.substr(start, text.find(';', start) - start);
}

inline void SetMethodOption(ScenarioConfig* s, const std::string& name, const std::string& key,
                            const std::string& value) {
  MethodInstance* m = s->FindMethod(name);
  ASSERT_NE(m, nullptr) << "no instance " << name;
  std::string why;
  ASSERT_TRUE(SetOption(m->method.get(), key, value, &why)) << why;
}

// Enables exactly the instances in `names` (in the scenario's order).
inline void EnableOnly(ScenarioConfig* s, const std::vector<std::string>& names) {
  for (MethodInstance& m : s->methods) {
    m.enabled = std::find(names.begin(), names.end(), m.name) != names.end();
  }
}

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
