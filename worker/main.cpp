// loom-worker: a render worker. Connects to loom-server, registers its GL
// capabilities, leases jobs and runs them on one headless EGL context
// (worker/worker_loop.h). `--probe` only makes the context and prints the
// capabilities.

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <thread>

#include "core/gl/egl_context.h"
#include "core/util/cli_main.h"
#include "core/util/termination_signals.h"
#include "core/version.h"
#include "rpc/auth.h"
#include "rpc/channel.h"
#include "worker/alive_file.h"
#include "worker/worker_loop.h"

namespace loom {
namespace {

int Probe(const gl::ContextOptions& options, bool json) {
  const auto context = gl::EglContext::Create(options);
  const gl::DeviceInfo& device = context->info();
  const unsigned cores = std::thread::hardware_concurrency();
  const double memory_gib =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE)) / (1u << 30);
  if (json) {
    std::cout << nlohmann::json{{"gl_vendor", device.gl_vendor}, {"gl_renderer", device.gl_renderer},
                                {"gl_version", device.gl_version}, {"egl_platform", device.platform},
                                {"egl_device_index", device.device_index},
                                {"software", device.software}, {"cores", cores}, {"memory_gib", memory_gib}}
                     .dump()
              << std::endl;
  } else {
    std::printf("GL: %s | %s | %s (EGL %s %d)\ncores: %u\nmemory: %.1f GiB\n", device.gl_vendor.c_str(),
                device.gl_renderer.c_str(), device.gl_version.c_str(), device.platform.c_str(), device.device_index,
                cores, memory_gib);
  }
  return 0;
}

int Main(int argc, char** argv) {
  TerminationSignals signals;  // before any thread starts
  CLI::App app{"loom-worker " + std::string(kVersion) + ": leases Loom jobs and runs them on a headless GL context"};
  app.set_version_flag("--version", kVersion);
  bool probe = false, json = false, software = false;
  int gl_device = -1;
  rpc::ChannelOptions channel;
  std::string token_file;
  double lease_wait_seconds = 10;
  std::string alive_file;
  app.add_flag("--probe", probe, "Make the EGL context and print this worker's capabilities, then exit");
  app.add_flag("--json", json, "With --probe: print the capabilities as one JSON object");
  app.add_flag("--software", software, "Use Mesa's software device (llvmpipe) even if a GPU is present");
  app.add_option("--gl-device", gl_device,
                 "EGL device index for the GL context (as --probe reports it): one worker per GPU on a machine "
                 "with several; default: the best device, an NVIDIA GPU first")
      ->check(CLI::Range(0, 255));
  app.add_option("--server", channel.address, "Server address")->capture_default_str();
  app.add_option("--token-file", token_file,
                 "File holding the worker token (the server's --worker-token-file); none: send no token")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-ca", channel.tls_ca_file, "PEM CA certificate: connect with TLS, verifying the server")
      ->check(CLI::ExistingFile);
  app.add_option("--lease-wait", lease_wait_seconds, "Seconds one lease request waits for work on the server")
      ->check(CLI::Range(0.1, 60.0))
      ->capture_default_str();
  app.add_option("--alive-file", alive_file,
                 "Liveness file: rewritten (one JSON line: unix_time, state, pid) whenever the worker's loop makes "
                 "progress, at least every --lease-wait seconds while idle, for `loom-healthcheck worker-alive` to "
                 "check its age. A probe's max age must exceed the longest gap between marks: an svbrdf render reports "
                 "nothing until it ends (seconds), a reference render every 1% of its pixel rows");
  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;

  worker::WorkerOptions options;
  options.gl.software_only = software;
  options.gl.device_index = gl_device;
  if (probe) return Probe(options.gl, json);

  if (!token_file.empty()) channel.token = rpc::ReadTokenFile(token_file);
  options.lease_wait = std::chrono::milliseconds(static_cast<int64_t>(lease_wait_seconds * 1000));
  options.label = "worker-" + std::to_string(::getpid());
  std::optional<worker::AliveFile> alive;
  if (!alive_file.empty()) {
    alive.emplace(alive_file);
    options.alive = [&alive](std::string_view state) { alive->Mark(state); };
  }
  worker::WorkerLoop loop(rpc::MakeChannel(channel), options);
  signals.Listen([&loop](int signal_number) {
    spdlog::info("signal {}: finishing or handing back the current job, then exiting", signal_number);
    loop.Stop();
  });
  loop.Run();
  return 0;
}

}  // namespace
}  // namespace loom

int main(int argc, char** argv) {
  return loom::RunMain("loom-worker", [&] { return loom::Main(argc, argv); });
}
