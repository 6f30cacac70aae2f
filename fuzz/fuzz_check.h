// The fuzz targets' contract check: a violated property prints what and the input's context, then
// traps, which libFuzzer reports as a crash (and the corpus replay as a failed test).
#pragma once

#include <cstdio>
#include <string>

namespace calibench {

inline void FuzzRequire(bool ok, const char* target, const char* what,
                        const std::string& context = "") {
  if (ok) return;
  std::fprintf(stderr, "%s: %s\n%s\n", target, what, context.c_str());
  __builtin_trap();
}

}  // namespace calibench
