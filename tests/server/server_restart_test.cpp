// loom-server as a process: SIGKILLed with jobs queued and one leased, restarted on
// the same data directory, nothing is lost and the leased job runs again; SIGTERM
// then stops it cleanly (exit 0).

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <set>

#include "client/job_client.h"
#include "rpc/channel.h"
#include "tests/server/service_fixture.h"
#include "tests/server/tiny_specs.h"

extern char** environ;

namespace loom::server {
namespace {

using namespace std::chrono_literals;

rpc::ChannelOptions Channel(const std::string& address) {
  rpc::ChannelOptions channel;
  channel.address = address;
  return channel;
}

// A port the kernel says is free now.
int FreePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t length = sizeof address;
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  close(fd);
  return ntohs(address.sin_port);
}

class ServerProcess {
 public:
  ServerProcess(const std::filesystem::path& data, int local_workers) : address_("127.0.0.1:" + std::to_string(FreePort())) {
    std::vector<std::string> arguments = {LOOM_SERVER, "--data", data.string(), "--listen", address_,
                                          "--local-workers", std::to_string(local_workers), "--lease-seconds", "3"};
    std::vector<char*> argv;
    for (std::string& argument : arguments) argv.push_back(argument.data());
    argv.push_back(nullptr);
    EXPECT_EQ(posix_spawn(&pid_, LOOM_SERVER, nullptr, nullptr, argv.data(), environ), 0);
    client_ = std::make_unique<client::JobClient>(rpc::MakeChannel(Channel(address_)));
    client_->WaitForServer(60s);
  }
  ~ServerProcess() {
    if (pid_ > 0) Signal(SIGKILL);
  }
  // Sends `signal` and returns the exit status.
  int Signal(int signal) {
    kill(pid_, signal);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return status;
  }
  client::JobClient& client() { return *client_; }
  const std::string& address() const { return address_; }

 private:
  std::string address_;
  pid_t pid_ = -1;
  std::unique_ptr<client::JobClient> client_;
};

TEST(ServerRestartTest, KilledWithJobsQueuedAndLeasedLosesNothing) {
  const auto data = std::filesystem::temp_directory_path() / ("loom-restart-test-" + std::to_string(::getpid()));
  std::filesystem::remove_all(data);
  std::set<std::string> ids;
  std::string leased_id;
  {
    ServerProcess server(data, 0);
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      v1::SubmitJobRequest request = PrecomputeRequest();
      request.mutable_precompute()->mutable_settings()->set_seed(seed);
      ids.insert(server.client().Submit(request).job().id());
    }
    // A worker leases one job, then the server dies under it.
    auto worker = v1::WorkerService::NewStub(rpc::MakeChannel(Channel(server.address())));
    grpc::ClientContext context;
    v1::LeaseJobRequest lease;
    lease.set_worker_id(RegisterWorker(*worker));
    lease.set_wait_ms(5000);
    v1::LeaseJobResponse leased;
    ASSERT_TRUE(worker->LeaseJob(&context, lease, &leased).ok());
    ASSERT_TRUE(leased.has_job());
    leased_id = leased.job().id();
    EXPECT_EQ(server.client().Get(leased_id).state(), v1::JOB_STATE_LEASED);
    const int status = server.Signal(SIGKILL);
    EXPECT_TRUE(WIFSIGNALED(status));
  }

  ServerProcess server(data, 1);
  for (const std::string& id : ids) {
    const v1::Job job = server.client().Watch(id, [](const v1::JobEvent&) {});
    EXPECT_EQ(job.state(), v1::JOB_STATE_SUCCEEDED) << id << ": " << job.error();
    if (id == leased_id) EXPECT_EQ(job.attempts(), 2u);  // the lease lost to the kill, then the run
    else EXPECT_EQ(job.attempts(), 1u);
  }
  EXPECT_EQ(server.client().ListFabrics().fabrics_size(), 3);
  const int status = server.Signal(SIGTERM);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
  std::filesystem::remove_all(data);
}

}  // namespace
}  // namespace loom::server
