#pragma once
// SIGINT and SIGTERM as an ordinary event for long-running binaries (loom-server,
// loom-worker): the signals are blocked in every thread and received by one thread
// with sigwait, so shutdown code runs as normal code, not in a signal handler.
// A second signal exits at once (128 + signal), for a shutdown that hangs.

#include <atomic>
#include <functional>
#include <thread>

namespace loom {

class TerminationSignals {
 public:
  // Blocks SIGINT and SIGTERM in the calling thread, and so in every thread it
  // starts afterwards: construct it first thing in main.
  TerminationSignals();
  // Stops listening (without calling the callback).
  ~TerminationSignals();
  TerminationSignals(const TerminationSignals&) = delete;
  TerminationSignals& operator=(const TerminationSignals&) = delete;

  // Calls `on_signal(signal_number)` on a listener thread when the first signal
  // arrives. Call once.
  void Listen(std::function<void(int)> on_signal);

 private:
  std::atomic<bool> closing_{false};
  std::thread listener_;
};

}  // namespace loom
