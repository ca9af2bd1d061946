// loom-lab validate | key: spec files and the fabric cache key.

#include <cstdio>

#include "core/spec/fabric_key.h"
#include "core/spec/spec_check.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/cli_main.h"
#include "lab/lab_command.h"

namespace loom::lab {

LabCommand AddValidateCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string kind, path;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("validate", "Check a spec file: strict JSON parse, then every range rule");
  command->add_option("kind", options->kind, "fabric, precompute, scene or animation")->required();
  command->add_option("file", options->path, "Spec file (JSON)")->required();
  return {command, [&flags, options] {
            const SpecCheck check = CheckSpecFile(ParseSpecKind(options->kind), options->path);
            if (flags.json) {
              PrintJson(SpecCheckJson(options->path, check));
            } else {
              std::fprintf(check.issues.empty() ? stdout : stderr, "%s",
                           SpecCheckText(options->path, ParseSpecKind(options->kind), check).c_str());
            }
            return check.issues.empty() ? 0 : ExitCodeFor(ErrorCode::kInvalidArgument);
          }};
}

LabCommand AddKeyCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    FabricInput input;
    bool canonical = false;
  };
  auto options = std::make_shared<Options>();
  auto* command =
      app.add_subcommand("key", "Print a fabric's cache key (content hash of fabric + precompute settings)");
  options->input.AddTo(command);
  command->add_flag("--canonical", options->canonical, "Also print the canonical form that is hashed");
  return {command, [&flags, options] {
            const auto fabric = options->input.LoadFabric();
            const auto settings = options->input.LoadSettings();
            ThrowIfAny(Validate(fabric, settings));
            const std::string canonical = CanonicalFabricJson(fabric, settings);
            const std::string key = FabricKey(fabric, settings);
            if (flags.json) {
              nlohmann::json figures = {{"key", key}, {"asset_format_version", kAssetFormatVersion}};
              if (options->canonical) figures["canonical"] = nlohmann::json::parse(canonical);
              PrintJson(figures);
            } else {
              std::printf("%s\n", key.c_str());
              if (options->canonical) std::printf("%s\n", canonical.c_str());
            }
            return 0;
          }};
}

}  // namespace loom::lab
