// Method options as text, without YAML: the canonical key of an instance's options (two instances
// with the same type and key compute the same result on the same measurements) and a setter by
// key and text value (what the CLI and tests use to change one option).
#pragma once

#include <string>

#include "methods/method.h"

namespace calibench {

// "key=value;key=value;..." in VisitOptions order, every number with 17 significant digits.
std::string OptionsKey(const Method& method);

// Sets option `key` of `method` from text ("1000", "true", "pinhole-k2"). False with *why for an
// unknown key, a value of the wrong type or options that then fail Check().
bool SetOption(Method* method, const std::string& key, const std::string& value, std::string* why);

}  // namespace calibench
