#pragma once
// A temp directory of this process's own under a `root` that other processes may
// share (DATA/tmp on a volume several servers mount): ROOT/<host>-<pid>-<random>,
// held by an flock on its ".lock" file while the object lives, and removed with
// its content by the destructor.
//
// Opening one removes what dead processes left under `root`: every directory
// whose lock no one holds (its process died, the kernel dropped the lock) and every
// loose file (from before directories of their own). A directory is renamed into
// place only once its lock is held, so a live one is never taken for a dead one.

#include <filesystem>

namespace loom::server {

class OwnTempDir {
 public:
  // Error(kUnavailable) naming the path when the directory cannot be made.
  explicit OwnTempDir(const std::filesystem::path& root);
  ~OwnTempDir();
  OwnTempDir(const OwnTempDir&) = delete;
  OwnTempDir& operator=(const OwnTempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int lock_fd_ = -1;
};

}  // namespace loom::server
