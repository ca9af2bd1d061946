// deploy/docker/loom-healthcheck, the images' and probes' one health check, run
// for real: against a server on loopback (with and without the right token) and
// as a worker probe on llvmpipe.

#include <gtest/gtest.h>

#include "binary_options.h"
#include "core/util/file_io.h"
#include "deploy_files.h"
#include "run_command.h"
#include "tests/server/service_fixture.h"

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

}  // namespace
}  // namespace loom::deploy_test
