#pragma once
// A loom-server in the test process on a free loopback port, with its data in a
// fresh temporary directory.

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "client/job_client.h"
#include "core/image/image.h"
#include "loom/v1/service.grpc.pb.h"
#include "rpc/channel.h"
#include "server/loom_server.h"
#include "tests/server/tiny_specs.h"

namespace loom::server {

// Channel options for `server` with `token` (none: the empty string).
rpc::ChannelOptions Channel(const LoomServer& server, const std::string& token);
// Stubs without the JobClient's error mapping, for tests of raw statuses.
std::unique_ptr<v1::LoomService::Stub> RawStub(const LoomServer& server, const std::string& token);
std::unique_ptr<v1::WorkerService::Stub> RawWorkerStub(const LoomServer& server, const std::string& token);
// Registers a worker by hand (as loom-worker does); returns its id.
std::string RegisterWorker(v1::WorkerService::Stub& stub);
grpc::Status RawSubmit(v1::LoomService::Stub& stub, const v1::SubmitJobRequest& request);
// An encoded image (a served frame) decoded; `name` gives its format (".exr").
Image ReadImageBytes(const std::string& bytes, const std::string& name);

// Jobs the server lists (of `kind`; UNSPECIFIED: all), up to 1000.
int JobCount(client::JobClient& client, v1::JobKind kind = v1::JOB_KIND_UNSPECIFIED);

class ServiceTest : public ::testing::Test {
 protected:
  // Starts a server with `options` filled in where the test left them default:
  // data dir, port 0, lease 3 s (a heartbeat a second) unless the test set one.
  void StartServer(ServerOptions options = {});
  void TearDown() override;

  // A client of the running server with `token` (none: the empty string).
  client::JobClient Client(const std::string& token = "");

  std::filesystem::path data_dir_;
  std::unique_ptr<LoomServer> server_;
};

}  // namespace loom::server
