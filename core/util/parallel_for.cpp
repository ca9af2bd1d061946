#include "core/util/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <barrier>
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

void ParallelRounds(size_t rounds, size_t count, unsigned threads, const std::function<void(size_t)>& prepare,
                    const std::function<void(size_t, size_t, unsigned)>& body,
                    const std::function<void(size_t)>& finish) {
  threads = static_cast<unsigned>(std::min<size_t>(ResolveThreadCount(threads), std::max<size_t>(count, 1)));
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  bool quit = false;  // written by the calling thread before it arrives at the round's first barrier
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto fail = [&] {
    const std::lock_guard lock(failure_mutex);
    if (!failure) failure = std::current_exception();
    stop = true;
  };
  auto items = [&](size_t round, unsigned worker) {
    try {
      for (size_t item; !stop && (item = next++) < count;) body(round, item, worker);
    } catch (...) {
      fail();
    }
  };

  // Two barriers a round: the first releases the team into the round's items (or
  // ends it), the second collects it before finish.
  std::barrier sync(static_cast<std::ptrdiff_t>(threads));
  std::vector<std::thread> team;
  team.reserve(threads - 1);
  for (unsigned worker = 1; worker < threads; ++worker) {
    team.emplace_back([&, worker] {
      for (size_t round = 0;; ++round) {
        sync.arrive_and_wait();
        if (quit) return;
        items(round, worker);
        sync.arrive_and_wait();
      }
    });
  }
  for (size_t round = 0; round < rounds && !stop; ++round) {
    try {
      prepare(round);
    } catch (...) {
      fail();
      break;
    }
    next = 0;
    sync.arrive_and_wait();
    items(round, 0);
    sync.arrive_and_wait();
    if (stop) break;
    try {
      finish(round);
    } catch (...) {
      fail();
    }
  }
  quit = true;
  sync.arrive_and_wait();
  for (std::thread& thread : team) thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace loom
