#include "worker/alive_file.h"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <exception>
#include <system_error>

#include "core/util/file_io.h"

namespace loom::worker {
namespace {

constexpr std::chrono::seconds kMinInterval{1};

}  // namespace

AliveFile::AliveFile(std::filesystem::path path, Clock clock) : path_(std::move(path)), clock_(std::move(clock)) {}

AliveFile::~AliveFile() {
  if (!last_write_) return;
  std::error_code error;  // a file that is gone already, or cannot go, is no reason to fail an exit
  std::filesystem::remove(path_, error);
}

void AliveFile::Mark(std::string_view state) {
  std::lock_guard lock(mu_);
  const auto now = clock_();
  if (last_write_ && now - *last_write_ < kMinInterval && state == last_state_) return;
  last_write_ = now;
  last_state_ = std::string(state);
  const nlohmann::ordered_json content{
      {"unix_time", std::chrono::duration_cast<std::chrono::seconds>(now.time_since_epoch()).count()},
      {"state", last_state_},
      {"pid", static_cast<int64_t>(::getpid())}};
  try {
    WriteFileAtomic(path_, content.dump() + "\n");
  } catch (const std::exception& error) {
    // The worker goes on working; its liveness probe will report the stale file.
    if (!std::exchange(warned_, true)) {
      spdlog::warn("cannot write the alive file {} (further failures are not logged): {}", path_.string(), error.what());
    }
  }
}

}  // namespace loom::worker
