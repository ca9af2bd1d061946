#include "core/util/cli_main.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/cfg/env.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>
#include <string>

namespace loom {

int ExitCodeFor(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidArgument: return 2;
    case ErrorCode::kNotFound: return 3;
    case ErrorCode::kUnavailable: return 4;
    case ErrorCode::kFailedPrecondition: return 5;
    case ErrorCode::kInternal: return 1;
  }
  return 1;
}

std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? 0 : ExitCodeFor(ErrorCode::kInvalidArgument);
  }
  return std::nullopt;
}

void RequireSubcommand(const CLI::App& app) {
  if (!app.get_subcommands().empty()) return;
  std::string names;
  for (const CLI::App* command : app.get_subcommands({})) names += (names.empty() ? "" : ", ") + command->get_name();
  throw Error(ErrorCode::kInvalidArgument, "a subcommand is required: one of " + names + " (see --help)");
}

int RunMain(std::string_view program, const std::function<int()>& body) {
  // Logs go to stderr so that --json output on stdout stays machine-readable.
  auto logger = spdlog::stderr_color_mt(std::string(program));
  spdlog::set_default_logger(logger);
  spdlog::cfg::load_env_levels();
  try {
    return body();
  } catch (const Error& error) {
    std::fprintf(stderr, "%.*s: %s\n", static_cast<int>(program.size()), program.data(), error.what());
    return ExitCodeFor(error.code());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%.*s: internal error: %s\n", static_cast<int>(program.size()), program.data(),
                 error.what());
    return 1;
  }
}

}  // namespace loom
