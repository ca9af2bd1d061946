#include "core/util/termination_signals.h"

#include <pthread.h>
#include <signal.h>

#include <cstdlib>

namespace loom {
namespace {

sigset_t TerminationSet() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

}  // namespace

TerminationSignals::TerminationSignals() {
  const sigset_t set = TerminationSet();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

TerminationSignals::~TerminationSignals() {
  if (!listener_.joinable()) return;
  closing_ = true;
  pthread_kill(listener_.native_handle(), SIGTERM);  // wakes sigwait; ignored while closing
  listener_.join();
}

void TerminationSignals::Listen(std::function<void(int)> on_signal) {
  listener_ = std::thread([this, on_signal = std::move(on_signal)] {
    const sigset_t set = TerminationSet();
    int signal_number = 0;
    if (sigwait(&set, &signal_number) != 0 || closing_) return;
    on_signal(signal_number);
    while (sigwait(&set, &signal_number) == 0 && !closing_) std::_Exit(128 + signal_number);
  });
}

}  // namespace loom
