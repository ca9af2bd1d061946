// loom: the client CLI. Submits precompute, render and animate jobs to loom-server and
// waits for them, lists, watches and cancels jobs, queries and downloads the fabric
// cache, and checks spec files locally exactly as the server will.

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <vector>

#include "client/client_command.h"
#include "core/util/cli_main.h"
#include "core/version.h"

namespace loom::client {
namespace {

int Main(int argc, char** argv) {
  CLI::App app{"loom " + std::string(kVersion) + ": submit and watch Loom render jobs"};
  app.set_version_flag("--version", kVersion);
  app.footer(
      "The token is read from --token-file or else LOOM_TOKEN (the server's --client-token-file).\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (command line, spec), 3 not found (file, job,\n"
      "fabric), 4 server unreachable, 5 refused (bad token, wrong state), 6 the job failed or was cancelled.");
  ClientFlags flags;
  app.add_flag("--json", flags.json, "Machine-readable output: one JSON object (JSON lines while waiting)");
  app.add_option("--server", flags.channel.address, "Server address")->capture_default_str();
  app.add_option("--token-file", flags.token_file, "File holding the client token (else LOOM_TOKEN)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-ca", flags.channel.tls_ca_file, "PEM CA certificate: connect with TLS, verifying the server")
      ->check(CLI::ExistingFile);

  std::vector<ClientCommand> commands;
  for (auto add : {AddSpecCommands, AddJobCommands, AddCacheCommands}) {
    for (ClientCommand& command : add(app, flags)) commands.push_back(std::move(command));
  }
  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;
  RequireSubcommand(app);
  for (const ClientCommand& command : commands) {
    if (command.command->parsed()) return command.run();
  }
  // A group (fabric, jobs, cache, spec) without its subcommand.
  for (const CLI::App* group : app.get_subcommands()) RequireSubcommand(*group);
  return ExitCodeFor(ErrorCode::kInternal);
}

}  // namespace
}  // namespace loom::client

int main(int argc, char** argv) {
  return loom::RunMain("loom", [&] { return loom::client::Main(argc, argv); });
}
