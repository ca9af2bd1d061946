// deploy/docker/loom-healthcheck, the images' and probes' one health check, run
// for real: against a server on loopback (with and without the right token), as a
// worker probe on llvmpipe, and as a worker liveness check of alive files, one of
// them written by a worker that has just run a job.

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "binary_options.h"
#include "core/util/file_io.h"
#include "deploy_files.h"
#include "rpc/channel.h"
#include "run_command.h"
#include "tests/server/service_fixture.h"
#include "worker/alive_file.h"
#include "worker/worker_loop.h"

namespace loom::deploy_test {
namespace {

// The script with the built binaries first on PATH, as in the images.
std::string Healthcheck(const std::string& environment, const std::string& arguments) {
  const std::string path = std::filesystem::path(LoomBinaryPath("loom")).parent_path().string() + ":" +
                           std::filesystem::path(LoomBinaryPath("loom-worker")).parent_path().string() + ":/usr/bin:/bin";
  return "env -i PATH=" + ShellQuote(path) + " " + environment + " sh " +
         ShellQuote((DeployDir() / "docker" / "loom-healthcheck").string()) + " " + arguments;
}

class HealthcheckTest : public server::ServiceTest {
 protected:
  void SetUp() override {
    server::ServerOptions options;
    options.local_workers = 0;
    options.client_token = "client-token-1";
    options.worker_token = "worker-token-1";
    StartServer(options);
    WriteFileAtomic(data_dir_ / "right", "client-token-1\n");
    WriteFileAtomic(data_dir_ / "wrong", "worker-token-1\n");
  }
  std::string Environment(const std::string& token_file, const std::string& address = "") const {
    return "LOOM_HEALTH_ADDRESS=" + (address.empty() ? server_->address() : address) +
           " LOOM_CLIENT_TOKEN_FILE=" + ShellQuote((data_dir_ / token_file).string());
  }
};

TEST_F(HealthcheckTest, ServerIsHealthyWithTheClientToken) {
  const CommandResult result = RunCommand(Healthcheck(Environment("right"), "server"));
  EXPECT_EQ(result.exit_code, 0) << result.output;
}

TEST_F(HealthcheckTest, ServerIsUnhealthyWithAWrongTokenOrNoServer) {
  const CommandResult wrong = RunCommand(Healthcheck(Environment("wrong"), "server"));
  EXPECT_NE(wrong.exit_code, 0) << wrong.output;
  EXPECT_NE(wrong.output.find("token"), std::string::npos) << wrong.output;
  // Port 1 on loopback: nothing listens there.
  const CommandResult absent = RunCommand(Healthcheck(Environment("right", "127.0.0.1:1"), "server"));
  EXPECT_NE(absent.exit_code, 0) << absent.output;
}

TEST(Healthcheck, WorkerIsHealthyWhenItsGlContextCanBeMade) {
  const CommandResult software = RunCommand(Healthcheck("", "worker --software"));
  EXPECT_EQ(software.exit_code, 0) << software.output;
  const CommandResult bad_flag = RunCommand(Healthcheck("", "worker --no-such-flag"));
  EXPECT_EQ(bad_flag.exit_code, 2) << bad_flag.output;
  const CommandResult no_role = RunCommand(Healthcheck("", "database"));
  EXPECT_EQ(no_role.exit_code, 2) << no_role.output;
}

TEST_F(HealthcheckTest, ARunningWorkersAliveFilePassesTheLivenessCheck) {
  const std::filesystem::path file = data_dir_ / "worker.alive";
  worker::AliveFile alive(file);
  worker::WorkerOptions options;
  options.lease_wait = std::chrono::milliseconds(500);
  options.alive = [&alive](std::string_view state) { alive.Mark(state); };
  rpc::ChannelOptions channel;
  channel.address = server_->address();
  channel.token = "worker-token-1";
  worker::WorkerLoop worker(rpc::MakeChannel(channel), options);
  std::thread thread([&worker] { worker.Run(); });
  client::JobClient client = Client("client-token-1");
  const v1::Job done = client.Watch(client.Submit(server::PrecomputeRequest()).job().id(), [](const v1::JobEvent&) {});
  EXPECT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  const CommandResult result = RunCommand(Healthcheck("", "worker-alive " + ShellQuote(file.string())));
  worker.Stop();
  thread.join();
  EXPECT_EQ(result.exit_code, 0) << result.output;
}

class WorkerAliveTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::remove_all(dir_);
    WriteFileAtomic(file_, R"({"unix_time": 1795478400, "state": "job 12: render", "pid": 7})" "\n");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Sets the file's modification time `seconds` back.
  void Age(int seconds) const {
    const auto now = std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch());
    const CommandResult touched =
        RunCommand("touch -d @" + std::to_string(now.count() - seconds) + " " + ShellQuote(file_.string()));
    ASSERT_EQ(touched.exit_code, 0) << touched.output;
  }
  CommandResult Check(const std::string& environment, const std::string& file) const {
    return RunCommand(Healthcheck(environment, "worker-alive " + (file.empty() ? "" : ShellQuote(file))));
  }

  const std::filesystem::path dir_ =
      std::filesystem::temp_directory_path() / ("loom-healthcheck-alive-" + std::to_string(::getpid()));
  const std::filesystem::path file_ = dir_ / "worker.alive";
};

TEST_F(WorkerAliveTest, AFreshFileIsAlive) {
  const CommandResult fresh = Check("", file_.string());
  EXPECT_EQ(fresh.exit_code, 0) << fresh.output;
  // The file from the environment when none is named.
  const CommandResult from_environment = Check("LOOM_WORKER_ALIVE_FILE=" + ShellQuote(file_.string()), "");
  EXPECT_EQ(from_environment.exit_code, 0) << from_environment.output;
}

TEST_F(WorkerAliveTest, AFileOlderThanTheLimitIsNotAliveAndTheMessageSaysWhy) {
  Age(400);
  const CommandResult stale = Check("", file_.string());
  EXPECT_EQ(stale.exit_code, 1) << stale.output;
  EXPECT_NE(stale.output.find(file_.string()), std::string::npos) << stale.output;
  EXPECT_NE(stale.output.find("limit of 300 s"), std::string::npos) << stale.output;
  EXPECT_NE(stale.output.find("job 12: render"), std::string::npos) << stale.output;  // its content
}

TEST_F(WorkerAliveTest, TheMaxAgeComesFromTheEnvironment) {
  Age(400);
  const CommandResult longer = Check("LOOM_WORKER_ALIVE_MAX_AGE=500", file_.string());
  EXPECT_EQ(longer.exit_code, 0) << longer.output;
  const CommandResult shorter = Check("LOOM_WORKER_ALIVE_MAX_AGE=350", file_.string());
  EXPECT_EQ(shorter.exit_code, 1) << shorter.output;
  EXPECT_NE(shorter.output.find("limit of 350 s"), std::string::npos) << shorter.output;
  const CommandResult bad = Check("LOOM_WORKER_ALIVE_MAX_AGE=5m", file_.string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("LOOM_WORKER_ALIVE_MAX_AGE"), std::string::npos) << bad.output;
}

TEST_F(WorkerAliveTest, AMissingFileIsNotAlive) {
  const std::string missing = (dir_ / "no-such.alive").string();
  const CommandResult result = Check("", missing);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find(missing), std::string::npos) << result.output;
}

}  // namespace
}  // namespace loom::deploy_test
