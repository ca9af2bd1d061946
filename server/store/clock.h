#pragma once
// Wall-clock time for the store, injectable so that lease expiry, stuck detection and
// timestamps can be tested by advancing a fake clock instead of sleeping.
//
// Only the store's *recorded* times come from here (Unix milliseconds, like
// loom.v1.JobTimings). Blocking waits (JobQueue::LeaseWait, WaitForChange) take
// std::chrono::steady_clock deadlines: they are real time by nature.

#include <atomic>
#include <chrono>
#include <cstdint>

namespace loom::server {

class Clock {
 public:
  virtual ~Clock() = default;
  // Unix time in milliseconds.
  virtual int64_t NowMs() const = 0;
};

class SystemClock final : public Clock {
 public:
  int64_t NowMs() const override {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  }
};

// For tests: time moves only when told to. Thread-safe.
class FakeClock final : public Clock {
 public:
  explicit FakeClock(int64_t start_ms = 1'700'000'000'000) : now_ms_(start_ms) {}
  int64_t NowMs() const override { return now_ms_.load(); }
  void Advance(int64_t ms) { now_ms_ += ms; }

 private:
  std::atomic<int64_t> now_ms_;
};

}  // namespace loom::server
