#include "core/util/subprocess.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "core/util/error.h"

extern char** environ;

namespace loom {

std::string FindOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  const std::string directories = path == nullptr ? "" : path;
  size_t start = 0;
  while (start <= directories.size()) {
    const size_t end = std::min(directories.find(':', start), directories.size());
    const std::filesystem::path candidate = std::filesystem::path(directories.substr(start, end - start)) / program;
    if (end > start && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return {};
}

void RunProgram(const std::string& program, const std::vector<std::string>& arguments,
                const std::string& install_hint) {
  const std::string path = FindOnPath(program);
  if (path.empty()) throw Error(ErrorCode::kUnavailable, program + " not found on PATH: " + install_hint);
  std::vector<std::string> strings = {path};
  strings.insert(strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& argument : strings) argv.push_back(argument.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, path.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    throw Error(ErrorCode::kUnavailable, "cannot start " + path);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error(ErrorCode::kInternal, program + " failed (its messages are above)");
  }
}

}  // namespace loom
