// UseSequentialOpenCv: OpenCV runs every call on the calling thread.
//
// Contract: call it once before the first OpenCV call that may run in parallel (chessboard
// detection, calibrateCamera); it is idempotent and thread-safe. calibench parallelises over
// trials and images itself (util/parallel_for.h), so OpenCV's own pool (TBB in Debian's build) only
// oversubscribes the cores, and it costs two things:
//   - calibrateCamera's sums are split differently from run to run, so its results change in the
//     last digits (docs/reliability.md: what stays different);
//   - its worker threads outlive main() and are torn down while LeakSanitizer stops the world at
//     exit, which crashes the leak check ("Tracer caught signal 11") now and then.
// The detectors (detect/chessboard.h), the batch solvers (batch/zhang.h) and the calibench
// executable call it; a program of its own that uses OpenCV should call it first.
#pragma once

namespace calibench {

void UseSequentialOpenCv();

}  // namespace calibench
