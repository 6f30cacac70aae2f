#include "util/format.h"

#include <cmath>
#include <cstdio>

namespace calibench {

std::string FormatNumber(double value, int significant_digits) {
  if (std::isnan(value)) return "nan";
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.*g", significant_digits, value);
  return buf;
}

}  // namespace calibench
