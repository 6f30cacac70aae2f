// The shared data directory of the tests labelled "data" (CALIBENCH_DATA_DIR, default
// ../shared/data). A test skips, saying so, only when the directory is absent; CI always has it.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace calibench {

inline const std::string kDataDir = CALIBENCH_DATA_DIR;

// Use as the first statement of a test: REQUIRE_DATA("zhang");
#define REQUIRE_DATA(sub)                                     \
  if (!std::filesystem::exists(kDataDir + "/" + sub))         \
  GTEST_SKIP() << "data directory " << kDataDir << "/" << sub \
               << " is absent (set CALIBENCH_DATA_DIR); CI always has it"

}  // namespace calibench
