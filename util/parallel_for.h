// ParallelFor: the one parallel loop of the project (the harness' trials, the rendered source's
// frames, the corner-bias study's cases).
//
// Contract:
//   ParallelFor(n, threads, body) calls body(worker, i) exactly once for every i in [0, n), on
//   min(threads, n) workers (threads <= 0: the hardware's concurrency), and returns when all
//   calls have returned. Indices are handed out in increasing order (worker w takes the next
//   free index when it is idle), so an index starts only after every smaller index has started.
//   `worker` is in [0, workers), so state that is expensive to make (a detector, a scratch
//   buffer) can be kept per worker and reused. The calling thread is worker 0, unless
//   options.spawn_every_worker: then it only waits, and every call runs on a spawned thread (the
//   harness: OpenCV's calibrateCamera differs in its last digits between the main thread and a
//   spawned one, docs/reliability.md).
//
// Determinism: which worker runs an index depends on timing. A body whose result depends only on
// i, written to slot i, gives the same results for every thread count; that is the rule every
// caller follows (random draws derive from the seed and the index, never from the worker).
// The body must not throw (library code reports failures through its results).
#pragma once

#include <cstddef>
#include <functional>

namespace calibench {

// The number of workers ParallelFor uses for n items: min(threads, n), at least 1; threads <= 0
// means std::thread::hardware_concurrency().
int ParallelWorkers(int threads, size_t n);

struct ParallelForOptions {
  int threads = 0;                  // <= 0: std::thread::hardware_concurrency().
  bool spawn_every_worker = false;  // True: the calling thread runs no call, it only waits.
};

void ParallelFor(size_t n, const ParallelForOptions& options,
                 const std::function<void(int worker, size_t i)>& body);
// ParallelFor with `threads` workers, the calling thread being worker 0.
inline void ParallelFor(size_t n, int threads,
                        const std::function<void(int worker, size_t i)>& body) {
  ParallelForOptions options;
  options.threads = threads;
  ParallelFor(n, options, body);
}

}  // namespace calibench
