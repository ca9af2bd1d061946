#pragma once
// Wall-clock time since construction (or the last Restart), on the monotonic clock:
// the figures every stage reports (seconds, frame milliseconds). And the process's
// CPU time, for costs that must not grow with the machine's load.

#include <time.h>

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

// CPU time of the whole process (every thread) since construction: what a
// computation costs whatever else the machine runs, where its wall time grows with
// the load. Meaningful while the process does nothing else.
class ProcessCpuStopwatch {
 public:
  ProcessCpuStopwatch() : start_(Now()) {}

  double Seconds() const { return Now() - start_; }

 private:
  static double Now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  double start_;
};

}  // namespace loom
