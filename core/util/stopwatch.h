#pragma once
// Wall-clock time since construction (or the last Restart), on the monotonic clock:
// the figures every stage reports (seconds, frame milliseconds).

#include <chrono>

namespace loom {

class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}

  void Restart() { start_ = Clock::now(); }
  double Seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  double Milliseconds() const { return 1e3 * Seconds(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

}  // namespace loom
