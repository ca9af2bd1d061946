#include "tests/server/service_fixture.h"

#include <grpcpp/client_context.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>

#include "core/util/file_io.h"
#include "rpc/channel.h"
#include "tests/server/store/postgres_server.h"

namespace loom::server {

Image ReadImageBytes(const std::string& bytes, const std::string& name) {
  const auto path = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "-" + name);
  WriteFileAtomic(path, bytes);
  Image image = ReadImage(path);
  std::filesystem::remove(path);
  return image;
}

void ServiceTest::StartServer(ServerOptions options) {
  static std::atomic<int> next{0};
  data_dir_ = std::filesystem::temp_directory_path() /
              ("loom-service-test-" + std::to_string(::getpid()) + "-" + std::to_string(next++));
  std::filesystem::remove_all(data_dir_);
  options.data_dir = data_dir_;
  // The same tests on PostgreSQL (ctest -L postgresql): a database of their own.
  if (const char* store = std::getenv("LOOM_TEST_STORE");
      store && std::string(store) == "postgresql" && options.store.empty()) {
    options.store = FreshPostgresDatabase();
  }
  options.listen = "127.0.0.1:0";
  if (options.lease_seconds == ServerOptions().lease_seconds) options.lease_seconds = 3;
  server_ = std::make_unique<LoomServer>(options);
}

void ServiceTest::TearDown() {
  server_.reset();
  if (!data_dir_.empty()) std::filesystem::remove_all(data_dir_);
}

client::JobClient ServiceTest::Client(const std::string& token) {
  return client::JobClient(rpc::MakeChannel(Channel(*server_, token)));
}

rpc::ChannelOptions Channel(const LoomServer& server, const std::string& token) {
  rpc::ChannelOptions channel;
  channel.address = server.address();
  channel.token = token;
  return channel;
}

std::unique_ptr<v1::LoomService::Stub> RawStub(const LoomServer& server, const std::string& token) {
  return v1::LoomService::NewStub(rpc::MakeChannel(Channel(server, token)));
}

std::unique_ptr<v1::WorkerService::Stub> RawWorkerStub(const LoomServer& server, const std::string& token) {
  return v1::WorkerService::NewStub(rpc::MakeChannel(Channel(server, token)));
}

std::string RegisterWorker(v1::WorkerService::Stub& stub) {
  grpc::ClientContext context;
  v1::RegisterWorkerResponse response;
  const grpc::Status status = stub.RegisterWorker(&context, v1::RegisterWorkerRequest(), &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response.worker_id();
}

grpc::Status RawSubmit(v1::LoomService::Stub& stub, const v1::SubmitJobRequest& request) {
  grpc::ClientContext context;
  v1::SubmitJobResponse response;
  return stub.SubmitJob(&context, request, &response);
}

int JobCount(client::JobClient& client, v1::JobKind kind) {
  v1::ListJobsRequest request;
  if (kind != v1::JOB_KIND_UNSPECIFIED) request.add_kinds(kind);
  request.set_page_size(1000);
  return client.List(request).jobs_size();
}

}  // namespace loom::server
