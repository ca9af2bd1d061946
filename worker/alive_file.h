#pragma once
// A worker's liveness signal: a small file the worker's loop rewrites as it makes
// progress, so that a probe (deploy/docker/loom-healthcheck worker-alive) can tell a
// hung worker from a busy one by the file's age. The lease heartbeat cannot: its own
// thread keeps beating while the work hangs.
//
// The file holds one line of JSON: {"unix_time": 1764000000, "state": "waiting for
// work", "pid": 42}. Writes are atomic (a temporary file renamed over the path) and
// at most one a second, except that a state different from the one last written is
// written at once, so that the file never shows a stale state (say "waiting for work"
// through a long render that started a moment after it). The loop's states change a
// few times per job, not per progress report. A write that fails is logged once and
// never stops the worker. On a clean exit (destruction) the file is removed, so that
// a worker restarted on the same path reads as not alive until it marks progress,
// not as alive on its predecessor's last word.

#include <chrono>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace loom::worker {

class AliveFile {
 public:
  using Clock = std::function<std::chrono::system_clock::time_point()>;

  // Writes nothing until the first Mark. Tests inject `clock`.
  explicit AliveFile(std::filesystem::path path, Clock clock = [] { return std::chrono::system_clock::now(); });
  // Removes the file if this object wrote it.
  ~AliveFile();
  AliveFile(const AliveFile&) = delete;
  AliveFile& operator=(const AliveFile&) = delete;

  // Thread-safe. Rewrites the file with `state` unless it was written less than a
  // second ago with the same state.
  void Mark(std::string_view state);

  const std::filesystem::path& path() const { return path_; }

 private:
  const std::filesystem::path path_;
  const Clock clock_;
  std::mutex mu_;
  std::optional<std::chrono::system_clock::time_point> last_write_;  // guarded by mu_
  std::string last_state_;                                          // guarded by mu_
  bool warned_ = false;                                             // guarded by mu_
};

}  // namespace loom::worker
