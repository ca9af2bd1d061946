#include "core/util/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace loom {

unsigned ResolveThreadCount(unsigned threads) {
  return threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
}

uint64_t PerWorkerCount::Total() const {
  uint64_t total = 0;
  for (const Padded& count : counts_) total += count.value;
  return total;
}

void ParallelFor(size_t count, unsigned threads, const std::function<void(size_t, unsigned)>& body,
                 const std::function<void(size_t)>& progress) {
  threads = static_cast<unsigned>(std::min<size_t>(ResolveThreadCount(threads), std::max<size_t>(count, 1)));
  std::atomic<size_t> next{0};
  std::atomic<size_t> done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto fail = [&] {
    const std::lock_guard lock(failure_mutex);
    if (!failure) failure = std::current_exception();
    stop = true;
  };

  // Runs items until none are left; the calling thread (worker 0) also reports.
  auto work = [&](unsigned worker) {
    const size_t step = std::max<size_t>(count / 100, 1);
    size_t reported = 0;
    try {
      for (size_t item; !stop && (item = next++) < count;) {
        body(item, worker);
        const size_t now = ++done;
        if (worker == 0 && progress && now >= reported + step) {
          reported = now;
          progress(now);
        }
      }
    } catch (...) {
      fail();
    }
  };

  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (unsigned worker = 1; worker < threads; ++worker) pool.emplace_back(work, worker);
  work(0);
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
  if (progress) progress(count);
}

}  // namespace loom
