#pragma once
// Runs a shell command for the deployment tests and captures what it printed.

#include <string>

namespace loom::deploy_test {

struct CommandResult {
  int exit_code = -1;  // -1: killed by a signal
  std::string output;  // stdout and stderr together
};

// `command` runs under /bin/sh; its stderr is merged into the output.
CommandResult RunCommand(const std::string& command);

// Single-quotes `text` for /bin/sh.
std::string ShellQuote(const std::string& text);

}  // namespace loom::deploy_test
