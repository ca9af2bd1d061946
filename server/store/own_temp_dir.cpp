#include "server/store/own_temp_dir.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <random>
#include <string>
#include <system_error>

#include "core/util/error.h"

namespace loom::server {
namespace {

constexpr const char* kLockFile = ".lock";
constexpr const char* kUnplaced = ".new-";  // a directory not yet locked and renamed into place

void Check(const std::error_code& ec, const std::string& what) {
  if (ec) throw Error(ErrorCode::kUnavailable, what + ": " + ec.message());
}

// Whether `dir`'s lock can be taken: no live process holds it.
bool Abandoned(const std::filesystem::path& dir) {
  const int fd = ::open((dir / kLockFile).c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return errno == ENOENT;  // placed without a lock file: a leftover, no process's
  const bool free = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
  ::close(fd);
  return free;
}

std::string UniqueName() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  std::random_device random;
  return std::string(host) + "-" + std::to_string(::getpid()) + "-" + std::to_string(random());
}

}  // namespace

OwnTempDir::OwnTempDir(const std::filesystem::path& root) {
  std::error_code ec;
  std::filesystem::create_directories(root, ec);
  Check(ec, "cannot create " + root.string());
  for (const auto& entry : std::filesystem::directory_iterator(root, ec)) {
    if (entry.path().filename().string().starts_with(kUnplaced)) continue;
    std::error_code ignored;
    if (!entry.is_directory(ignored) || Abandoned(entry.path())) std::filesystem::remove_all(entry.path(), ignored);
  }
  Check(ec, "cannot list " + root.string());
  const std::string name = UniqueName();
  const auto unplaced = root / (kUnplaced + name);
  std::filesystem::create_directory(unplaced, ec);
  Check(ec, "cannot create " + unplaced.string());
  lock_fd_ = ::open((unplaced / kLockFile).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ >= 0 && ::flock(lock_fd_, LOCK_EX) == 0) {
    path_ = root / name;
    std::filesystem::rename(unplaced, path_, ec);
  } else {
    ec.assign(errno, std::generic_category());
  }
  if (ec) {
    if (lock_fd_ >= 0) ::close(lock_fd_);
    std::error_code ignored;
    std::filesystem::remove_all(unplaced, ignored);
    Check(ec, "cannot make a temp directory under " + root.string());
  }
}

OwnTempDir::~OwnTempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

}  // namespace loom::server
