// Two loom-worker processes drain 200 small render jobs, or a frame range of a
// mesh sequence; one is SIGKILLed part way. Its lease expires, the job goes to the
// other worker, and every job (every frame) ends SUCCEEDED exactly once.

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "client/frame_range.h"
#include "core/animate/animation.h"
#include "core/animate/cloth_sequence_io.h"
#include "core/spec/spec_json.h"
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

// `loom render --frames 0..23` as the CLI does it: a hanging cloth's sequence
// uploaded once, a job a frame, the frames gathered in order.
TEST_F(ServiceTest, AFrameRangeWhoseWorkerIsKilledRendersEachFrameOnce) {
  ServerOptions options;
  options.local_workers = 0;
  options.lease_seconds = 3;
  StartServer(options);
  client::JobClient client = Client();
  const v1::AnimationSpec hanging = ParseSpecJson<v1::AnimationSpec>(R"({
    "cloth": {"loops": 6, "courses": 8, "wale_axis": {"z": -1}},
    "pins": [{"course": 0}], "initial_velocity": {"y": 2}, "frames_per_second": 8, "duration_seconds": 2.875})",
                                                                     "animation");
  animate::WriteGltfSequence(animate::ClothSequence(animate::RunAnimation(hanging)), data_dir_ / "hanging.glb");
  v1::SceneSpec scene = TinyScene(24, 16);
  v1::SceneObject& cloth = *scene.mutable_objects(0);
  cloth.clear_fabric();
  cloth.mutable_mesh()->set_gltf_path("hanging.glb");
  // In view as in animate_job_test.
  v1::Vec3& scale = *cloth.mutable_transform()->mutable_scale();
  scale.set_x(0.3f);
  scale.set_y(0.3f);
  scale.set_z(0.3f);
  cloth.mutable_transform()->mutable_translation()->set_x(-0.75f);
  cloth.mutable_transform()->mutable_translation()->set_z(1.0f);
  const std::vector<int> sequence_objects = client::SequenceObjects(scene);
  EXPECT_EQ(client.UploadMeshes(scene, data_dir_), 1);
  v1::SubmitJobRequest request = RenderRequest(scene);
  request.set_client_request_id("range");

  // Past the sequence's 24 frames: refused before anything is queued.
  EXPECT_THROW(client::SubmitFrameRange(client, request, sequence_objects, {0, 24}), Error);
  EXPECT_EQ(client.List({}).jobs_size(), 0);

  const client::FrameRange range{0, 23};
  const std::vector<v1::SubmitJobResponse> responses =
      client::SubmitFrameRange(client, request, sequence_objects, range);
  ASSERT_EQ(responses.size(), 24u);
  const pid_t doomed = SpawnWorker(server_->address());
  const pid_t survivor = SpawnWorker(server_->address());
  EXPECT_EQ(client.Watch(responses[3].job().id(), [](const v1::JobEvent&) {}).state(), v1::JOB_STATE_SUCCEEDED);
  kill(doomed, SIGKILL);
  waitpid(doomed, nullptr, 0);

  std::set<std::string> frames;
  for (uint32_t i = 0; i < range.size(); ++i) {
    const v1::Job job = client.Watch(responses[i].job().id(), [](const v1::JobEvent&) {});
    ASSERT_EQ(job.state(), v1::JOB_STATE_SUCCEEDED) << "frame " << i << ": " << job.error();
    EXPECT_EQ(job.render().scene().objects(0).mesh().frame(), i);
    EXPECT_EQ(CountLines(client.Log(job.id()), "SUCCEEDED"), 1) << "frame " << i;
    ASSERT_EQ(job.result_artifacts_size(), 1);
    frames.insert(job.result_artifacts(0));
  }
  EXPECT_GT(frames.size(), 12u);  // the cloth swings: most frames differ
  EXPECT_EQ(client.List({}).jobs_size(), 24);  // one job a frame, no more
  // The same range with the same request id: the same jobs, nothing new.
  const std::vector<v1::SubmitJobResponse> again = client::SubmitFrameRange(client, request, sequence_objects, range);
  for (uint32_t i = 0; i < range.size(); ++i) EXPECT_EQ(again[i].job().id(), responses[i].job().id());
  EXPECT_EQ(client.List({}).jobs_size(), 24);
  kill(survivor, SIGTERM);
  waitpid(survivor, nullptr, 0);
}

}  // namespace
}  // namespace loom::server
