// Running the calibench executable from a test: its exit status and everything it printed.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "tests/common/temp_files.h"

namespace calibench {

struct CliRun {
  int status = -1;     // std::system's raw status (0: success).
  int exit_code = -1;  // The exit code, -1 when the process did not exit normally.
  std::string output;  // stdout and stderr.
};

// `binary` with `args` (a shell command line), its output captured in a file of the test temp dir
// named after the running test (CTest runs the tests of a file in parallel).
inline CliRun RunCli(const std::string& binary, const std::string& args) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string out =
      ::testing::TempDir() + "cli_" +
      (test ? std::string(test->test_suite_name()) + "." + test->name() : std::string("out")) +
      ".txt";
  CliRun run;
  run.status = std::system((binary + " " + args + " > " + out + " 2>&1").c_str());
  run.exit_code = WIFEXITED(run.status) ? WEXITSTATUS(run.status) : -1;
  run.output = Slurp(out);
  return run;
}

}  // namespace calibench
