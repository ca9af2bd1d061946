// loom-worker: a render worker. Today it probes the machine: it makes the headless
// EGL context it will render with and prints the capabilities it will register
// with the server. Leasing jobs arrives with the job service.

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <thread>

#include "core/gl/egl_context.h"
#include "core/util/cli_main.h"
#include "core/version.h"

namespace loom {
namespace {

int Main(int argc, char** argv) {
  CLI::App app{"loom-worker " + std::string(kVersion) + ": leases Loom jobs and runs them on a headless GL context"};
  app.set_version_flag("--version", kVersion);
  bool probe = false, json = false, software = false;
  app.add_flag("--probe", probe, "Make the EGL context and print this worker's capabilities, then exit");
  app.add_flag("--json", json, "Print the capabilities as one JSON object");
  app.add_flag("--software", software, "Use Mesa's software device (llvmpipe) even if a GPU is present");

  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;
  if (!probe) {
    throw Error(ErrorCode::kInvalidArgument,
                "this build has no job service to connect to yet; `loom-worker --probe` checks this machine's GL");
  }

  gl::ContextOptions options = gl::DefaultContextOptions();
  options.software_only = software;
  const auto context = gl::EglContext::Create(options);
  const gl::DeviceInfo& device = context->info();
  const unsigned cores = std::thread::hardware_concurrency();
  const double memory_gib =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE)) / (1u << 30);
  if (json) {
    std::cout << nlohmann::json{{"gl_vendor", device.gl_vendor}, {"gl_renderer", device.gl_renderer},
                                {"gl_version", device.gl_version}, {"egl_platform", device.platform},
                                {"software", device.software}, {"cores", cores}, {"memory_gib", memory_gib}}
                     .dump()
              << std::endl;
  } else {
    std::printf("GL: %s | %s | %s (EGL %s)\ncores: %u\nmemory: %.1f GiB\n", device.gl_vendor.c_str(),
                device.gl_renderer.c_str(), device.gl_version.c_str(), device.platform.c_str(), cores, memory_gib);
  }
  return 0;
}

}  // namespace
}  // namespace loom

int main(int argc, char** argv) {
  return loom::RunMain("loom-worker", [&] { return loom::Main(argc, argv); });
}
