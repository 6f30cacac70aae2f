// `calibench report`: runs the report, the Python package calibench_report (python/), on run
// directories. The interpreter: ReportArgs::python, else $CALIBENCH_PYTHON, else python3 on PATH
// and, when that one cannot import the report or its modules, /usr/bin/python3. The package:
// $CALIBENCH_REPORT_PYTHONPATH, else the build tree's copy (python/ beside or above the
// executable's directory), else the installed one (pip install --no-deps ./python).
#pragma once

#include <string>
#include <vector>

namespace calibench {

struct ReportArgs {
  std::vector<std::string> dirs;  // Run output directories.
  std::string out;                // Report directory ("": the report's default).
  std::string python;             // Interpreter ("": searched as above).
};

// The report's exit code; 2 with a message naming what is missing when no interpreter runs it.
int Report(const ReportArgs& args, const char* argv0);

}  // namespace calibench
