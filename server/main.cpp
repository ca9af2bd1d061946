// loom-server: the job service (queue, fabric cache, artifacts). This build has the
// command line only; the gRPC service, its SQLite queue and `--local-workers` arrive
// with the job-service work (DESIGN.md "Server, worker, client").

#include <CLI/CLI.hpp>

#include "core/util/cli_main.h"
#include "core/version.h"

namespace loom {
namespace {

int Main(int argc, char** argv) {
  CLI::App app{"loom-server " + std::string(kVersion) + ": Loom's job queue, fabric cache and artifact store"};
  app.set_version_flag("--version", kVersion);
  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;
  throw Error(ErrorCode::kUnavailable,
              "the job service is not in this build yet; use `loom-lab` to run the engine directly");
}

}  // namespace
}  // namespace loom

int main(int argc, char** argv) {
  return loom::RunMain("loom-server", [&] { return loom::Main(argc, argv); });
}
