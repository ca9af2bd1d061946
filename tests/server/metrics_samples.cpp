#include "tests/server/metrics_samples.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>

#include <unistd.h>

#include "core/util/file_io.h"

namespace loom::server {

std::map<std::string, double> Samples(const std::string& text) {
  std::map<std::string, double> samples;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    const size_t space = line.rfind(' ');
    samples[line.substr(0, space)] = std::stod(line.substr(space + 1));
  }
  return samples;
}

double Sample(const std::string& text, const std::string& name) {
  const auto samples = Samples(text);
  const auto found = samples.find(name);
  if (found == samples.end()) {
    ADD_FAILURE() << name << " not in the scrape:\n" << text;
    return -1;
  }
  return found->second;
}

namespace {

// Runs `promtool <command>` on `file_text` written to a file ("<" in `command`:
// given on stdin).
std::string RunPromtool(const std::string& command, const std::string& file_text) {
  // One file per call: ctest runs this binary's tests in parallel processes.
  static int calls = 0;
  const auto file = std::filesystem::path(::testing::TempDir()) /
                    ("loom_promtool_" + std::to_string(::getpid()) + "_" + std::to_string(++calls) + ".yml");
  WriteFileAtomic(file, file_text);
  const std::string line = "promtool " + command + " '" + file.string() + "' 2>&1";
  FILE* pipe = popen(line.c_str(), "r");
  if (!pipe) return "cannot run " + line;
  std::string output;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  const int status = pclose(pipe);
  std::filesystem::remove(file);
  if (status == 0) return "";
  return line + " exited " + std::to_string(status) + ": " + output;
}

}  // namespace

std::string PromtoolProblems(const std::string& text) { return RunPromtool("check metrics <", text); }

std::string PromtoolOnFile(const std::string& command, const std::string& file_text) {
  return RunPromtool(command, file_text);
}

}  // namespace loom::server
