// loom: the client CLI. Today it checks spec files exactly as the server will;
// submitting jobs and querying the fabric cache arrive with the job service.

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "core/spec/spec_check.h"
#include "core/util/cli_main.h"
#include "core/version.h"

namespace loom {
namespace {

int Main(int argc, char** argv) {
  CLI::App app{"loom " + std::string(kVersion) + ": submit and watch Loom render jobs"};
  app.set_version_flag("--version", kVersion);
  bool json = false;
  app.add_flag("--json", json, "Machine-readable output (one JSON object)");

  auto* spec = app.add_subcommand("spec", "Work with spec files");
  spec->require_subcommand(1);
  std::string kind, path;
  bool show_normalized = false;
  auto* check = spec->add_subcommand("check", "Check a spec file as the server would (strict parse + every limit)");
  check->add_option("kind", kind, "fabric, precompute or scene")->required();
  check->add_option("file", path, "Spec file (JSON)")->required();
  check->add_flag("--normalized", show_normalized, "Print the spec with every default made explicit");

  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;
  RequireSubcommand(app);

  const SpecCheck result = CheckSpecFile(ParseSpecKind(kind), path);
  if (json) {
    nlohmann::json out = SpecCheckJson(path, result);
    if (show_normalized) out["normalized"] = nlohmann::json::parse(result.normalized_json);
    std::cout << out.dump() << std::endl;
  } else {
    if (result.issues.empty()) std::printf("%s: valid %s spec\n", path.c_str(), kind.c_str());
    else std::fprintf(stderr, "%s", FormatIssues(result.issues).c_str());
    if (show_normalized) std::printf("%s\n", result.normalized_json.c_str());
  }
  return result.issues.empty() ? 0 : ExitCodeFor(ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace loom

int main(int argc, char** argv) {
  return loom::RunMain("loom", [&] { return loom::Main(argc, argv); });
}
