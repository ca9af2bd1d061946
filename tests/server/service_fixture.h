#pragma once
// A loom-server in the test process on a free loopback port, with its data in a
// fresh temporary directory.

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "client/job_client.h"
#include "loom/v1/service.pb.h"
#include "server/loom_server.h"
#include "tests/server/tiny_specs.h"

namespace loom::server {

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
