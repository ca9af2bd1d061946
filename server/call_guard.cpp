#include "server/call_guard.h"

#include <chrono>
#include <mutex>

namespace loom::server {

void WarnRefused(std::string_view call, const std::string& peer) {
  using Clock = std::chrono::steady_clock;
  static std::mutex mu;
  static Clock::time_point last_logged;
  static uint64_t unlogged = 0;
  uint64_t skipped = 0;
  {
    std::lock_guard lock(mu);
    const Clock::time_point now = Clock::now();
    if (last_logged != Clock::time_point() && now - last_logged < std::chrono::seconds(1)) {
      ++unlogged;
      return;
    }
    last_logged = now;
    skipped = std::exchange(unlogged, 0);
  }
  if (skipped > 0) {
    spdlog::warn("{} from {}: missing or wrong bearer token ({} more refused call(s) since the last warning)", call,
                 peer, skipped);
  } else {
    spdlog::warn("{} from {}: missing or wrong bearer token", call, peer);
  }
}

}  // namespace loom::server
