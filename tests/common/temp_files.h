// Files in tests: a whole file as a string, and a fresh (emptied) folder under the test temp dir.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace calibench {

// The file's bytes; "" when it cannot be read.
inline std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// testing::TempDir()/<prefix><name>, removed if it exists (not created).
inline std::string FreshTempDir(const std::string& prefix, const std::string& name) {
  std::string dir = testing::TempDir() + prefix + name;
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace calibench
