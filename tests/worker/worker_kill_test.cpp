// Two loom-worker processes drain 200 small render jobs; one is SIGKILLed part way.
// Its lease expires, the job goes to the other worker, and every job ends
// SUCCEEDED exactly once.

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/server/service_fixture.h"
#include "worker/job_runner.h"

extern char** environ;

namespace loom::server {
namespace {

pid_t SpawnWorker(const std::string& address) {
  std::vector<std::string> arguments = {LOOM_WORKER, "--server", address, "--lease-wait", "1"};
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawn(&pid, LOOM_WORKER, nullptr, nullptr, argv.data(), environ), 0);
  return pid;
}

// TMPDIR/loom-worker-<pid>-* (worker/job_runner.h).
int ScratchDirectoriesOf(pid_t pid) {
  const std::string prefix = "loom-worker-" + std::to_string(pid) + "-";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::temp_directory_path())) {
    count += entry.path().filename().string().starts_with(prefix);
  }
  return count;
}

int CountLines(const std::vector<std::string>& lines, const std::string& text) {
  int count = 0;
  for (const std::string& line : lines) count += line.find(text) != std::string::npos;
  return count;
}

TEST_F(ServiceTest, TwoHundredJobsTwoWorkersOneKilledEveryJobSucceedsOnce) {
  ServerOptions options;
  options.local_workers = 0;
  options.lease_seconds = 3;  // the killed worker's job comes back within seconds
  StartServer(options);
  client::JobClient client = Client();
  std::vector<std::string> ids;
  for (int i = 0; i < 200; ++i) ids.push_back(client.Submit(RenderRequest(TinyScene(16, 12))).job().id());

  const pid_t doomed = SpawnWorker(server_->address());
  const pid_t survivor = SpawnWorker(server_->address());
  // Part way through the batch, kill one worker without warning.
  EXPECT_EQ(client.Watch(ids[60], [](const v1::JobEvent&) {}).state(), v1::JOB_STATE_SUCCEEDED);
  kill(doomed, SIGKILL);
  waitpid(doomed, nullptr, 0);

  for (const std::string& id : ids) {
    const v1::Job job = client.Watch(id, [](const v1::JobEvent&) {});
    EXPECT_EQ(job.state(), v1::JOB_STATE_SUCCEEDED) << id << ": " << job.error();
    EXPECT_EQ(job.result_artifacts_size(), 1) << id;
    EXPECT_EQ(CountLines(client.Log(id), "SUCCEEDED"), 1) << id;
  }
  kill(survivor, SIGTERM);
  int status = 0;
  waitpid(survivor, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;

  // Scratch directories: the SIGTERMed worker removed its own; the SIGKILLed one
  // could not, and the next worker to start removes it (here, or any other process
  // making a JobRunner meanwhile: tests run in parallel).
  EXPECT_EQ(ScratchDirectoriesOf(survivor), 0);
  worker::JobRunner next_worker(gl::DefaultContextOptions());
  EXPECT_EQ(ScratchDirectoriesOf(doomed), 0);
}

}  // namespace
}  // namespace loom::server
