// `calibench report`: the interpreter and package search of report_cmd.h, and the run.
#include "bench/app/report_cmd.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace calibench {
namespace {

// A small bootstrap runs the package's main and names a module it cannot import.
constexpr int kCannotImport = 120;  // The bootstrap's exit code when an import fails.
constexpr int kCannotExec = 127;    // The child's, when the interpreter cannot be run.
constexpr const char* kBootstrap =
    "import sys\n"
    "last = sys.argv.pop(1) == '1'\n"
    "try:\n"
    "    from calibench_report.cli import main\n"
    "except ImportError as e:\n"
    "    if last:\n"
    "        print(f'calibench report: {sys.executable} cannot import {e.name or e} ({e})',\n"
    "              file=sys.stderr)\n"
    "    sys.exit(120)\n"  // kCannotImport.
    "sys.exit(main())\n";

// The executable file `name` in a directory of $PATH, or "".
std::string FindOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return "";
  const std::string dirs = path;
  size_t start = 0;
  while (start <= dirs.size()) {
    size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
    std::string candidate = dir + "/" + name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return "";
}

// The directory holding calibench_report for PYTHONPATH, or "" (then an installed one is used).
std::string ReportPackageDir(const char* argv0, std::string* why) {
  const auto holds = [](const std::filesystem::path& dir) {
    std::error_code ec;
    return std::filesystem::exists(dir / "calibench_report" / "__main__.py", ec);
  };
  if (const char* env = std::getenv("CALIBENCH_REPORT_PYTHONPATH")) {
    if (holds(env)) return env;
    *why = std::string(env) + "/calibench_report: not found (CALIBENCH_REPORT_PYTHONPATH)";
    return "";
  }
  std::error_code ec;
  std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) exe = std::filesystem::absolute(argv0, ec);
  for (const std::filesystem::path& dir :
       {exe.parent_path() / "python", exe.parent_path().parent_path() / "python"}) {
    if (holds(dir)) return dir.lexically_normal().string();
  }
  return "";
}

// Runs `python` on the bootstrap; its exit code, kCannotImport or kCannotExec.
int RunReportPython(const std::string& python, bool last, const std::vector<std::string>& args) {
  std::vector<std::string> argv = {python, "-c", kBootstrap, last ? "1" : "0"};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> c_argv;
  c_argv.reserve(argv.size() + 1);
  for (std::string& a : argv) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);
  std::cout.flush();
  const pid_t pid = ::fork();
  if (pid < 0) return kCannotExec;
  if (pid == 0) {
    ::execvp(c_argv[0], c_argv.data());
    ::_exit(kCannotExec);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return kCannotExec;
  }
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

}  // namespace

int Report(const ReportArgs& a, const char* argv0) {
  std::string why;
  const std::string package_dir = ReportPackageDir(argv0, &why);
  if (!why.empty()) {
    std::cerr << "calibench: report: " << why << "\n";
    return 2;
  }
  if (!package_dir.empty()) {
    const char* python_path = std::getenv("PYTHONPATH");
    const std::string path =
        package_dir +
        (python_path != nullptr && *python_path ? ":" + std::string(python_path) : "");
    ::setenv("PYTHONPATH", path.c_str(), 1);
  }
  std::vector<std::string> pythons;  // Tried in order.
  const char* env = std::getenv("CALIBENCH_PYTHON");
  if (!a.python.empty()) {
    pythons = {a.python};
  } else if (env != nullptr && *env) {
    pythons = {env};
  } else {
    const std::string on_path = FindOnPath("python3");
    std::error_code ec;
    if (!on_path.empty()) pythons.push_back(on_path);
    if (on_path.empty() || !std::filesystem::equivalent(on_path, "/usr/bin/python3", ec)) {
      if (std::filesystem::exists("/usr/bin/python3", ec)) pythons.push_back("/usr/bin/python3");
    }
  }
  std::vector<std::string> args = {"--out", a.out};
  args.insert(args.end(), a.dirs.begin(), a.dirs.end());
  std::string tried;
  for (size_t i = 0; i < pythons.size(); ++i) {
    const int code = RunReportPython(pythons[i], i + 1 == pythons.size(), args);
    if (code != kCannotImport && code != kCannotExec) return code;
    tried += (tried.empty() ? "" : ", ") + pythons[i] +
             (code == kCannotExec ? " (cannot be run)" : " (cannot import the report)");
  }
  std::cerr << "calibench: report: no Python interpreter runs the report: "
            << (tried.empty() ? "python3 is not on PATH" : "tried " + tried)
            << ". It needs python3 with numpy, scipy, pandas, matplotlib, statsmodels, tabulate "
               "and PyYAML, and the package calibench_report (the build tree's python/, "
               "CALIBENCH_REPORT_PYTHONPATH, or pip install --no-deps ./python); choose the "
               "interpreter with --python or CALIBENCH_PYTHON (docs/install.md)\n";
  return 2;
}

}  // namespace calibench
