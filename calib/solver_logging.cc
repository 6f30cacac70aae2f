#include "calib/solver_logging.h"

#include <glog/logging.h>

#include <mutex>

namespace calibench {

void ConfigureSolverLogging(const char* program, bool verbose) {
  static std::once_flag initialised;
  std::call_once(initialised, [program] {
    FLAGS_logtostderr = true;  // No log files in /tmp.
    google::InitGoogleLogging(program);
  });
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  FLAGS_v = verbose ? 1 : 0;  // Ceres's per-iteration lines are VLOG(1).
}

}  // namespace calibench
