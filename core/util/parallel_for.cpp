#include "core/util/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <barrier>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace loom {

unsigned ResolveThreadCount(unsigned threads) {
  return threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
}

namespace {

// The threads a loop over `count` items runs on.
unsigned LoopThreads(unsigned threads, size_t count) {
  return static_cast<unsigned>(std::min<size_t>(ResolveThreadCount(threads), std::max<size_t>(count, 1)));
}

// The first exception any thread of a loop threw, and whether the loop should stop.
class FirstFailure {
 public:
  // From a catch block.
  void Catch() {
    const std::lock_guard lock(mutex_);
    if (!failure_) failure_ = std::current_exception();
    stop_ = true;
  }
  bool stopped() const { return stop_; }
  void RethrowIfAny() const {
    if (failure_) std::rethrow_exception(failure_);
  }

 private:
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::exception_ptr failure_;
};

}  // namespace

uint64_t PerWorkerCount::Total() const {
  uint64_t total = 0;
  for (const Padded& count : counts_) total += count.value;
  return total;
}

namespace {

// The helper threads every ParallelFor shares, started when first wanted and kept
// (a simulation runs thousands of short loops a second; starting threads for each
// costs more than some of the loops). A loop asks for helpers; idle helpers join
// it, each taking the next worker index, until it has enough or its owner, which
// works too, runs out of items. Loops from several threads run side by side; a
// loop started inside a loop's body runs on its own thread alone (no helper waits
// on another).
class HelperPool {
 public:
  using Work = std::function<void(unsigned worker)>;

  static HelperPool& Get() {
    static HelperPool pool;
    return pool;
  }
  static bool InsideALoop() { return depth_ > 0; }

  // Runs work(0) here and work(1 … helpers) on helpers that are free before the
  // caller's own work(0) ends; returns when every one that joined has finished.
  void Run(unsigned helpers, const Work& work) {
    Loop loop{&work, helpers};
    {
      const std::lock_guard lock(mutex_);
      // Grown to the most helpers a loop asked for, and kept.
      while (threads_.size() < helpers) threads_.emplace_back([this] { Serve(); });
      open_.push_back(&loop);
    }
    wake_.notify_all();
    ++depth_;
    work(0);
    --depth_;
    std::unique_lock lock(mutex_);
    std::erase(open_, &loop);  // no helper joins from here on
    loop.finished.wait(lock, [&] { return loop.running == 0; });
  }

  ~HelperPool() {
    {
      const std::lock_guard lock(mutex_);
      quit_ = true;
    }
    wake_.notify_all();
    for (std::thread& thread : threads_) thread.join();
  }

 private:
  struct Loop {
    const Work* work;
    unsigned wanted;          // helpers still wanted
    unsigned next_worker = 1;
    unsigned running = 0;     // helpers inside work
    std::condition_variable finished;
  };

  HelperPool() = default;

  void Serve() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return quit_ || !open_.empty(); });
      if (quit_) return;
      Loop& loop = *open_.front();
      const unsigned worker = loop.next_worker++;
      if (--loop.wanted == 0) open_.erase(open_.begin());
      ++loop.running;
      lock.unlock();
      ++depth_;
      (*loop.work)(worker);
      --depth_;
      lock.lock();
      if (--loop.running == 0) loop.finished.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Loop*> open_;  // loops wanting helpers, oldest first
  bool quit_ = false;
  std::vector<std::thread> threads_;
  static thread_local int depth_;
};

thread_local int HelperPool::depth_ = 0;

}  // namespace

void ParallelFor(size_t count, unsigned threads, const std::function<void(size_t, unsigned)>& body,
                 const std::function<void(size_t)>& progress) {
  threads = HelperPool::InsideALoop() ? 1 : LoopThreads(threads, count);
  std::atomic<size_t> next{0};
  std::atomic<size_t> done{0};
  FirstFailure failure;

  // Runs items until none are left; the calling thread (worker 0) also reports.
  auto work = [&](unsigned worker) {
    const size_t step = std::max<size_t>(count / 100, 1);
    size_t reported = 0;
    try {
      for (size_t item; !failure.stopped() && (item = next++) < count;) {
        body(item, worker);
        const size_t now = ++done;
        if (worker == 0 && progress && now >= reported + step) {
          reported = now;
          progress(now);
        }
      }
    } catch (...) {
      failure.Catch();
    }
  };

  if (threads == 1) {
    work(0);
  } else {
    HelperPool::Get().Run(threads - 1, work);
  }
  failure.RethrowIfAny();
  if (progress) progress(count);
}

void ParallelRounds(size_t rounds, size_t count, unsigned threads, const std::function<void(size_t)>& prepare,
                    const std::function<void(size_t, size_t, unsigned)>& body,
                    const std::function<void(size_t)>& finish) {
  threads = LoopThreads(threads, count);
  std::atomic<size_t> next{0};
  bool quit = false;  // written by the calling thread before it arrives at the round's first barrier
  FirstFailure failure;
  auto items = [&](size_t round, unsigned worker) {
    try {
      for (size_t item; !failure.stopped() && (item = next++) < count;) body(round, item, worker);
    } catch (...) {
      failure.Catch();
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
  for (size_t round = 0; round < rounds && !failure.stopped(); ++round) {
    try {
      prepare(round);
    } catch (...) {
      failure.Catch();
      break;
    }
    next = 0;
    sync.arrive_and_wait();
    items(round, 0);
    sync.arrive_and_wait();
    if (failure.stopped()) break;
    try {
      finish(round);
    } catch (...) {
      failure.Catch();
    }
  }
  quit = true;
  sync.arrive_and_wait();
  for (std::thread& thread : team) thread.join();
  failure.RethrowIfAny();
}

}  // namespace loom
