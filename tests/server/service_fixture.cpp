#include "tests/server/service_fixture.h"

#include <unistd.h>

#include <atomic>

#include "rpc/channel.h"

namespace loom::server {

void ServiceTest::StartServer(ServerOptions options) {
  static std::atomic<int> next{0};
  data_dir_ = std::filesystem::temp_directory_path() /
              ("loom-service-test-" + std::to_string(::getpid()) + "-" + std::to_string(next++));
  std::filesystem::remove_all(data_dir_);
  options.data_dir = data_dir_;
  options.listen = "127.0.0.1:0";
  options.lease_seconds = 3;
  server_ = std::make_unique<LoomServer>(options);
}

void ServiceTest::TearDown() {
  server_.reset();
  if (!data_dir_.empty()) std::filesystem::remove_all(data_dir_);
}

client::JobClient ServiceTest::Client(const std::string& token) {
  rpc::ChannelOptions channel;
  channel.address = server_->address();
  channel.token = token;
  return client::JobClient(rpc::MakeChannel(channel));
}

}  // namespace loom::server
