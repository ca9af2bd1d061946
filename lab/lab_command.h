#pragma once
// loom-lab's subcommands. Each Add*Command registers its CLI11 subcommand and
// returns what to run when it is chosen; main() parses and runs the chosen one.

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>

#include "core/gl/egl_context.h"
#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"

namespace loom::lab {

// Flags every subcommand shares.
struct LabFlags {
  bool json = false;  // print one JSON object with the figures
};

struct LabCommand {
  CLI::App* command;
  std::function<int()> run;  // returns the exit code
};

LabCommand AddInfoCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddTestSceneCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddValidateCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddKeyCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddCompareCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddGeometryCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddYarnSectionCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddLumisliceCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddAcquireCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddFitCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddPrecomputeCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddRenderCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddSweepCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddChartCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddPlanCommand(CLI::App& app, const LabFlags& flags);
LabCommand AddAnimateCommand(CLI::App& app, const LabFlags& flags);

// Shared by the GL subcommands: --software, and the context it asks for.
struct GlFlags {
  bool software = false;
  int device = -1;  // EGL device index; −1: the best
};
void AddGlFlags(CLI::App* command, GlFlags* flags);
std::unique_ptr<gl::EglContext> MakeContext(const GlFlags& flags);

// A fabric spec file and an optional precompute settings file (defaults when
// absent), the input of every fabric subcommand.
struct FabricInput {
  std::string fabric, settings;
  void AddTo(CLI::App* command);
  v1::FabricSpec LoadFabric() const;
  v1::PrecomputeSettings LoadSettings() const;
};

// A precompute settings file; the empty path gives the defaults.
v1::PrecomputeSettings LoadSettingsFile(const std::string& path);

nlohmann::json DeviceJson(const gl::DeviceInfo& info);
void PrintJson(const nlohmann::json& figures);

}  // namespace loom::lab
