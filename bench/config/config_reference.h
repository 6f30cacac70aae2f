// The reference documentation of the scenario format, generated from its declarations
// (scenario_fields.cc) and from every registered method type's VisitOptions: the part of
// docs/configuration.md between its GENERATED markers (`calibench config-reference`).
#pragma once

#include <string>

namespace calibench {

// Markdown: one table per mapping of the scenario (key, type, default, unit, meaning), then the
// options of every method type.
std::string ConfigurationReference();

}  // namespace calibench
