// Numbers as calibench writes them into text (CSV files, sweep point names): one definition.
#pragma once

#include <string>

namespace calibench {

// `value` with `significant_digits` digits ("%.<digits>g"), or "nan". CSV files use the default
// 10 digits; sweep ranges use 12 so that computed values such as 0.1 * 3 print as 0.3.
std::string FormatNumber(double value, int significant_digits = 10);

}  // namespace calibench
