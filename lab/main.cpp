// loom-lab: the engine without the server, for research and measurement.
// Every subcommand can print one JSON object with its figures (--json).

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "core/gl/egl_context.h"
#include "core/image/image.h"
#include "core/render/test_scene.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_check.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/cli_main.h"
#include "core/version.h"

namespace loom {
namespace {

nlohmann::json DeviceJson(const gl::DeviceInfo& info) {
  return {{"platform", info.platform},     {"device_index", info.device_index},
          {"egl_vendor", info.egl_vendor}, {"gl_vendor", info.gl_vendor},
          {"gl_renderer", info.gl_renderer}, {"gl_version", info.gl_version},
          {"software", info.software}};
}

void PrintJson(const nlohmann::json& figures) { std::cout << figures.dump() << std::endl; }

struct GlFlags {
  bool software = false;
};

void AddGlFlags(CLI::App* command, GlFlags* flags) {
  command->add_flag("--software", flags->software, "Use Mesa's software device (llvmpipe) even if a GPU is present");
}

std::unique_ptr<gl::EglContext> MakeContext(const GlFlags& flags) {
  gl::ContextOptions options = gl::DefaultContextOptions();
  options.software_only = flags.software;
  return gl::EglContext::Create(options);
}

int Main(int argc, char** argv) {
  CLI::App app{"loom-lab " + std::string(kVersion) +
               ": Loom's engine without the server, for research and measurement"};
  app.set_version_flag("--version", kVersion);
  bool json = false;
  app.add_flag("--json", json, "Print one JSON object with the figures instead of text");

  // info
  GlFlags info_gl;
  auto* info = app.add_subcommand("info", "Create a headless OpenGL context and report the device");
  AddGlFlags(info, &info_gl);

  // test-scene
  GlFlags scene_gl;
  TestSceneOptions scene_options;
  std::string scene_out;
  auto* test_scene = app.add_subcommand("test-scene", "Render the GL test scene through headless EGL to an image");
  test_scene->add_option("--out,-o", scene_out, "Output image (.png sRGB or .exr linear)")->required();
  test_scene->add_option("--width", scene_options.width, "Width in pixels")->check(CLI::Range(1, 8192));
  test_scene->add_option("--height", scene_options.height, "Height in pixels")->check(CLI::Range(1, 8192));
  test_scene->add_option("--msaa", scene_options.msaa_samples, "MSAA samples")->check(CLI::IsMember({1, 2, 4, 8}));
  AddGlFlags(test_scene, &scene_gl);

  // validate
  std::string validate_kind, validate_path;
  auto* validate = app.add_subcommand("validate", "Check a spec file: strict JSON parse, then every range rule");
  validate->add_option("kind", validate_kind, "fabric, precompute or scene")->required();
  validate->add_option("file", validate_path, "Spec file (JSON)")->required();

  // key
  std::string key_fabric, key_settings;
  bool key_canonical = false;
  auto* key = app.add_subcommand("key", "Print a fabric's cache key (content hash of fabric + precompute settings)");
  key->add_option("fabric", key_fabric, "Fabric spec file (JSON)")->required();
  key->add_option("--settings", key_settings, "Precompute settings file (JSON); defaults if absent");
  key->add_flag("--canonical", key_canonical, "Also print the canonical form that is hashed");

  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;
  RequireSubcommand(app);

  if (*info) {
    const auto context = MakeContext(info_gl);
    const gl::DeviceInfo& device = context->info();
    if (json) {
      PrintJson(DeviceJson(device));
    } else {
      std::printf("platform: EGL %s\nGL vendor: %s\nGL renderer: %s\nGL version: %s\nsoftware: %s\n",
                  device.platform.c_str(), device.gl_vendor.c_str(), device.gl_renderer.c_str(),
                  device.gl_version.c_str(), device.software ? "yes" : "no");
    }
    return 0;
  }

  if (*test_scene) {
    FormatFromPath(scene_out);  // reject a bad extension before any work
    const auto start = std::chrono::steady_clock::now();
    const auto context = MakeContext(scene_gl);
    const auto rendered = std::chrono::steady_clock::now();
    const Image image = RenderTestScene(*context, scene_options);
    const auto drawn = std::chrono::steady_clock::now();
    WriteImage(image, scene_out);
    const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    if (json) {
      PrintJson({{"output", scene_out},
                 {"width", image.width},
                 {"height", image.height},
                 {"msaa_samples", scene_options.msaa_samples},
                 {"context_ms", ms(start, rendered)},
                 {"render_ms", ms(rendered, drawn)},
                 {"device", DeviceJson(context->info())}});
    } else {
      std::printf("wrote %s (%dx%d, %d× MSAA) on %s in %.1f ms\n", scene_out.c_str(), image.width, image.height,
                  scene_options.msaa_samples, context->info().gl_renderer.c_str(), ms(rendered, drawn));
    }
    return 0;
  }

  if (*validate) {
    const SpecCheck check = CheckSpecFile(ParseSpecKind(validate_kind), validate_path);
    if (json) {
      nlohmann::json issues = nlohmann::json::array();
      for (const ValidationIssue& issue : check.issues) issues.push_back({{"path", issue.path}, {"message", issue.message}});
      PrintJson({{"file", validate_path}, {"valid", check.issues.empty()}, {"issues", issues}});
    } else if (check.issues.empty()) {
      std::printf("%s: valid %s spec\n", validate_path.c_str(), validate_kind.c_str());
    } else {
      std::fprintf(stderr, "%s", FormatIssues(check.issues).c_str());
    }
    return check.issues.empty() ? 0 : ExitCodeFor(ErrorCode::kInvalidArgument);
  }

  if (*key) {
    const auto fabric = LoadSpecFile<v1::FabricSpec>(key_fabric, "fabric");
    const auto settings = key_settings.empty() ? v1::PrecomputeSettings()
                                               : LoadSpecFile<v1::PrecomputeSettings>(key_settings, "precompute");
    ValidationIssues issues = Validate(fabric);
    const ValidationIssues settings_issues = Validate(settings);
    issues.insert(issues.end(), settings_issues.begin(), settings_issues.end());
    ThrowIfAny(issues);
    const std::string canonical = CanonicalFabricJson(fabric, settings);
    const std::string fabric_key = FabricKey(fabric, settings);
    if (json) {
      nlohmann::json figures = {{"key", fabric_key}, {"asset_format_version", kAssetFormatVersion}};
      if (key_canonical) figures["canonical"] = nlohmann::json::parse(canonical);
      PrintJson(figures);
    } else {
      std::printf("%s\n", fabric_key.c_str());
      if (key_canonical) std::printf("%s\n", canonical.c_str());
    }
    return 0;
  }
  return ExitCodeFor(ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace loom

int main(int argc, char** argv) {
  return loom::RunMain("loom-lab", [&] { return loom::Main(argc, argv); });
}
