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

void ParallelFor(size_t n, int threads, const std::function<void(int worker, size_t i)>& body) {
  if (n == 0) return;
  const int workers = ParallelWorkers(threads, n);
  std::atomic<size_t> next{0};
  auto loop = [&](int worker) {
    for (size_t i = next++; i < n; i = next++) body(worker, i);
  };
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (int w = 1; w < workers; ++w) pool.emplace_back(loop, w);
  loop(0);
  for (std::thread& t : pool) t.join();
}

}  // namespace calibench
