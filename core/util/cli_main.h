#pragma once
// What every Loom binary does around its main: log to stderr through spdlog, turn a
// loom::Error into "<program>: <message>" and an exit code that says what failed.
//
// Exit codes (stable; scripts use them):
//   0 success, 1 internal error, 2 bad input (flags or spec), 3 not found,
//   4 unavailable (no GL context, server unreachable), 5 failed precondition.

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <string_view>

#include "core/util/error.h"

namespace loom {

int ExitCodeFor(ErrorCode code);

// Parses the command line. Returns an exit code when the program should stop now:
// 0 after --help or --version, 2 (with CLI11's message) for a bad command line.
std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv);

// Throws Error(kInvalidArgument) listing the subcommands if none was given.
// (CLI11's own require_subcommand would hide an unknown flag behind
// "A subcommand is required".)
void RequireSubcommand(const CLI::App& app);

// Runs `body`, returning its exit code or the code of the error it threw.
int RunMain(std::string_view program, const std::function<int()>& body);

}  // namespace loom
