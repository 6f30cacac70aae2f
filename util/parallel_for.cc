#include "util/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace calibench {

int ParallelWorkers(int threads, size_t n) {
  if (threads <= 0) threads = static_cast<int>(std::thread::hardware_concurrency());
  const size_t workers = std::min<size_t>(std::max(threads, 1), std::max<size_t>(n, 1));
  return static_cast<int>(workers);
}

void ParallelFor(size_t n, const ParallelForOptions& options,
                 const std::function<void(int worker, size_t i)>& body) {
  if (n == 0) return;
  const int workers = ParallelWorkers(options.threads, n);
  std::atomic<size_t> next{0};
  auto loop = [&](int worker) {
    for (size_t i = next++; i < n; i = next++) body(worker, i);
  };
  std::vector<std::thread> pool;
  const int first_spawned = options.spawn_every_worker ? 0 : 1;
  pool.reserve(workers - first_spawned);
  for (int w = first_spawned; w < workers; ++w) pool.emplace_back(loop, w);
  if (first_spawned == 1) loop(0);
  for (std::thread& t : pool) t.join();
}

}  // namespace calibench
