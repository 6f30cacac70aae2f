// Real data for the tests labelled "data", from two places:
// - the small public sets bundled in the repository's data/ (CALIBENCH_BUNDLED_DATA_DIR,
//   data/README.md). They are part of the sources, so a missing file fails the test: BundledData.
// - the larger sets in CALIBENCH_DATA_DIR (default ../shared/data), whose tests are also labelled
//   "shared-data". They skip, saying so, only when the folder is absent (REQUIRE_SHARED_DATA); CI
//   always has it. `ctest -LE shared-data` runs what a clone alone must pass.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace calibench {

inline const std::string kBundledDataDir = CALIBENCH_BUNDLED_DATA_DIR;
inline const std::string kSharedDataDir = CALIBENCH_DATA_DIR;

// The path of a bundled file or folder, e.g. BundledData("opencv-left"). Records a failure (the
// test goes on and fails where it reads the path) when it is absent: that is a broken checkout.
inline std::string BundledData(const std::string& sub) {
  std::string path = kBundledDataDir + "/" + sub;
  if (!std::filesystem::exists(path)) {
    ADD_FAILURE() << "bundled data " << path << " is missing (it is part of the repository)";
  }
  return path;
}

// Use as the first statement of a test labelled shared-data: REQUIRE_SHARED_DATA("zhang");
#define REQUIRE_SHARED_DATA(sub)                                             \
  if (!std::filesystem::exists(kSharedDataDir + "/" + (sub)))                \
  GTEST_SKIP() << "shared data directory " << kSharedDataDir << "/" << (sub) \
               << " is absent (set CALIBENCH_DATA_DIR); CI always has it"

}  // namespace calibench
