// The reference documentation of the scenario format, generated from its declarations
// (scenario_fields.cc) and from every registered method type's VisitOptions: the part of
// docs/configuration.md between its GENERATED markers (`calibench config-reference`), and the
// method types' part alone (`calibench methods`).
#pragma once

#include <string>

#include "methods/registry.h"

namespace calibench {

// Markdown: one table per mapping of the scenario (key, type, default, unit, meaning), then the
// options of every method type.
std::string ConfigurationReference();

// Markdown: a method type's name, whether the map form of `methods:` enables it by default, its
// one-line description, then its options (key, type, default, unit, meaning) as its VisitOptions
// declares them. ConfigurationReference() holds one per registered type.
std::string MethodTypeReference(const MethodType& type);

// `calibench methods [--type NAME]`: MethodTypeReference() of every registered type in registry
// order, or of the type `type` alone (`type` not empty). False when no type has that name, with
// *why naming it, the closest type name and every registered one.
bool MethodsReference(const std::string& type, std::string* text, std::string* why);

}  // namespace calibench
