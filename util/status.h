// What every calibench algorithm returns besides its estimate: a status, a message, iteration
// counts and timings (after Ceres' Solver::Summary). A bad case is a status, never an abort.
#pragma once

#include <chrono>
#include <string>
#include <utility>

namespace calibench {

enum class MethodStatus {
  kOk,        // Ran to completion; the estimate is usable.
  kDiverged,  // Stopped by a divergence guard (non-finite state, a depth <= 0).
  kFailed,    // Invalid input or a degenerate problem; no estimate.
};

inline const char* ToString(MethodStatus s) {
  switch (s) {
    case MethodStatus::kOk:
      return "ok";
    case MethodStatus::kDiverged:
      return "diverged";
    case MethodStatus::kFailed:
      return "failed";
  }
  return "failed";
}

struct MethodSummary {
  MethodStatus status = MethodStatus::kFailed;
  std::string message;
  long iterations = 0;  // Accepted integrator steps (adaptive) or solver iterations (batch).
  double wall_ms = 0.0;
  bool IsUsable() const { return status == MethodStatus::kOk; }
};

// Times an algorithm from construction; Finish() stamps a summary with status, message and the
// elapsed wall time, and returns a copy to hand back:
//   const SummaryClock clock;  ...  return clock.Finish(&summary, MethodStatus::kOk, "");
class SummaryClock {
 public:
  SummaryClock() : start_(std::chrono::steady_clock::now()) {}
  template <typename Summary>
  Summary Finish(Summary* summary, MethodStatus status, const std::string& message) const {
    summary->status = status;
    summary->message = message;
    summary->wall_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
            .count();
    return *summary;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace calibench
