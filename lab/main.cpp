// loom-lab: the engine without the server, for research and measurement.
// Every subcommand can print one JSON object with its figures (--json).

#include <vector>

#include "core/util/cli_main.h"
#include "core/version.h"
#include "lab/lab_command.h"

namespace loom::lab {
namespace {

int Main(int argc, char** argv) {
  CLI::App app{"loom-lab " + std::string(kVersion) +
               ": Loom's engine without the server, for research and measurement"};
  app.set_version_flag("--version", kVersion);
  LabFlags flags;
  app.add_flag("--json", flags.json, "Print one JSON object with the figures instead of text");

  const std::vector<LabCommand> commands = {
      AddInfoCommand(app, flags),
      AddTestSceneCommand(app, flags),
      AddValidateCommand(app, flags),
      AddKeyCommand(app, flags),
      AddGeometryCommand(app, flags),
      AddYarnSectionCommand(app, flags),
      AddLumisliceCommand(app, flags),
      AddAcquireCommand(app, flags),
      AddFitCommand(app, flags),
      AddPrecomputeCommand(app, flags),
      AddRenderCommand(app, flags),
      AddCompareCommand(app, flags),
      AddSweepCommand(app, flags),
      AddChartCommand(app, flags),
      AddPlanCommand(app, flags),
      AddAnimateCommand(app, flags),
  };
  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;
  RequireSubcommand(app);
  for (const LabCommand& command : commands) {
    if (command.command->parsed()) return command.run();
  }
  return ExitCodeFor(ErrorCode::kInternal);
}

}  // namespace
}  // namespace loom::lab

int main(int argc, char** argv) {
  return loom::RunMain("loom-lab", [&] { return loom::lab::Main(argc, argv); });
}
