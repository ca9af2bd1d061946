#include "server/refusal_log.h"

#include <google/protobuf/stubs/logging.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdint>
#include <mutex>
#include <utility>

namespace loom::server {

void WarnRefused(std::string_view message) {
  using Clock = std::chrono::steady_clock;
  static std::mutex mu;
  static Clock::time_point last_written;
  static uint64_t unwritten = 0;
  uint64_t skipped = 0;
  {
    std::lock_guard lock(mu);
    const Clock::time_point now = Clock::now();
    if (last_written != Clock::time_point() && now - last_written < std::chrono::seconds(1)) {
      ++unwritten;
      return;
    }
    last_written = now;
    skipped = std::exchange(unwritten, 0);
  }
  if (skipped > 0) {
    spdlog::warn("{} ({} more refused input(s) since the last warning)", message, skipped);
  } else {
    spdlog::warn("{}", message);
  }
}

void RouteProtobufLogs() {
  google::protobuf::SetLogHandler([](google::protobuf::LogLevel level, const char* file, int line,
                                     const std::string& message) {
    if (level >= google::protobuf::LOGLEVEL_WARNING) {
      WarnRefused(std::string("protobuf: ") + message);
    } else {
      spdlog::debug("protobuf {}:{}: {}", file, line, message);
    }
  });
}

}  // namespace loom::server
