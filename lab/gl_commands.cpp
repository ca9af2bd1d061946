// loom-lab info | test-scene: the headless GL path.

#include <cstdio>
#include <iostream>

#include "core/image/image.h"
#include "core/render/test_scene.h"
#include "core/util/stopwatch.h"
#include "lab/lab_command.h"

namespace loom::lab {

void AddGlFlags(CLI::App* command, GlFlags* flags) {
  command->add_flag("--software", flags->software, "Use Mesa's software device (llvmpipe) even if a GPU is present");
  command->add_option("--gl-device", flags->device,
                      "EGL device index (as `info` reports it); default: the best device, an NVIDIA GPU first")
      ->check(CLI::Range(0, 255));
}

std::unique_ptr<gl::EglContext> MakeContext(const GlFlags& flags) {
  gl::ContextOptions options = gl::DefaultContextOptions();
  options.software_only = flags.software;
  options.device_index = flags.device;
  return gl::EglContext::Create(options);
}

nlohmann::json DeviceJson(const gl::DeviceInfo& info) {
  return {{"platform", info.platform},       {"device_index", info.device_index},
          {"egl_vendor", info.egl_vendor},   {"gl_vendor", info.gl_vendor},
          {"gl_renderer", info.gl_renderer}, {"gl_version", info.gl_version},
          {"software", info.software}};
}

void PrintJson(const nlohmann::json& figures) { std::cout << figures.dump() << std::endl; }

LabCommand AddInfoCommand(CLI::App& app, const LabFlags& flags) {
  auto gl_flags = std::make_shared<GlFlags>();
  auto* command = app.add_subcommand("info", "Create a headless OpenGL context and report the device");
  AddGlFlags(command, gl_flags.get());
  return {command, [&flags, gl_flags] {
            const auto context = MakeContext(*gl_flags);
            const gl::DeviceInfo& device = context->info();
            if (flags.json) {
              PrintJson(DeviceJson(device));
            } else {
              std::printf("platform: EGL %s\nGL vendor: %s\nGL renderer: %s\nGL version: %s\nsoftware: %s\n",
                          device.platform.c_str(), device.gl_vendor.c_str(), device.gl_renderer.c_str(),
                          device.gl_version.c_str(), device.software ? "yes" : "no");
            }
            return 0;
          }};
}

LabCommand AddTestSceneCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    GlFlags gl;
    TestSceneOptions scene;
    std::string out;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("test-scene", "Render the GL test scene through headless EGL to an image");
  command->add_option("--out,-o", options->out, "Output image (.png sRGB or .exr linear)")->required();
  command->add_option("--width", options->scene.width, "Width in pixels")->check(CLI::Range(1, 8192));
  command->add_option("--height", options->scene.height, "Height in pixels")->check(CLI::Range(1, 8192));
  command->add_option("--msaa", options->scene.msaa_samples, "MSAA samples")->check(CLI::IsMember({1, 2, 4, 8}));
  AddGlFlags(command, &options->gl);
  return {command, [&flags, options] {
            FormatFromPath(options->out);  // reject a bad extension before any work
            Stopwatch stopwatch;
            const auto context = MakeContext(options->gl);
            const double context_ms = stopwatch.Milliseconds();
            stopwatch.Restart();
            const Image image = RenderTestScene(*context, options->scene);
            const double render_ms = stopwatch.Milliseconds();
            WriteImage(image, options->out);
            if (flags.json) {
              PrintJson({{"output", options->out},
                         {"width", image.width},
                         {"height", image.height},
                         {"msaa_samples", options->scene.msaa_samples},
                         {"context_ms", context_ms},
                         {"render_ms", render_ms},
                         {"device", DeviceJson(context->info())}});
            } else {
              std::printf("wrote %s (%dx%d, %d× MSAA) on %s in %.1f ms\n", options->out.c_str(), image.width,
                          image.height, options->scene.msaa_samples, context->info().gl_renderer.c_str(),
                          render_ms);
            }
            return 0;
          }};
}

}  // namespace loom::lab
