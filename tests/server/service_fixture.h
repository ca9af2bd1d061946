#pragma once
// A loom-server in the test process on a free loopback port, with its data in a
// fresh temporary directory, and the small specs the service tests submit: a
// precompute small enough to run in a second or two on llvmpipe, and a small scene
// that uses it.

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "client/job_client.h"
#include "loom/v1/service.pb.h"
#include "server/loom_server.h"

namespace loom::server {

// 8×8 texels, 16 views × 16 lights, 1 lobe, no indirect light, 1 sub-sample.
v1::PrecomputeSettings TinySettings();
// The standard knit.
v1::FabricSpec KnitFabric();
// A knit plane seen at 45°, one shadowing light, `width`×`height` pixels, with
// TinySettings; EXR output.
v1::SceneSpec TinyScene(uint32_t width = 64, uint32_t height = 48);

v1::SubmitJobRequest PrecomputeRequest();
v1::SubmitJobRequest RenderRequest(const v1::SceneSpec& scene);

class ServiceTest : public ::testing::Test {
 protected:
  // Starts a server with `options` filled in where the test left them default:
  // data dir, port 0, lease 3 s (a heartbeat a second).
  void StartServer(ServerOptions options = {});
  void TearDown() override;

  // A client of the running server with `token` (none: the empty string).
  client::JobClient Client(const std::string& token = "");

  std::filesystem::path data_dir_;
  std::unique_ptr<LoomServer> server_;
};

}  // namespace loom::server
