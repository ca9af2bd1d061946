// A render job's meshes stay pinned (kept from eviction) while the job may still
// run, and are released however it ends, including the endings that happen inside
// the queue: the last attempt's lease expiring, a failed dependency, a cancel, a
// restart voiding the last attempt's lease. Its frames are pinned when its worker
// completes it and stay so for the result retention after it ended.

#include <grpcpp/server_context.h>
#include <gtest/gtest.h>

#include "core/util/error.h"
#include "server/job_submission.h"
#include "server/service_state.h"
#include "server/worker_service.h"
#include "tests/server/store/store_test_util.h"
#include "tests/server/tiny_specs.h"

namespace loom::server {
namespace {

const JobQueueOptions kOneAttempt{.lease_duration_ms = 30'000, .default_max_attempts = 1};

// An uploaded unit quad; `variant` makes its bytes, so its artifact, distinct.
std::string PutQuad(ArtifactStore& artifacts, int variant) {
  return artifacts.Put("# quad " + std::to_string(variant) +
                       "\nv -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n");
}

// TinyScene with its cloth on `mesh`; `method` svbrdf depends on a precompute.
v1::SubmitJobRequest RenderOfMesh(const std::string& mesh, v1::RenderMethod method) {
  v1::SceneSpec scene = TinyScene(16, 16);
  scene.mutable_objects(0)->mutable_mesh()->set_artifact(mesh);
  scene.mutable_render()->set_method(method);
  return RenderRequest(scene);
}

// Whether `hash` is pinned: an unpinned artifact can be removed (and is).
bool Pinned(ArtifactStore& artifacts, const std::string& hash) {
  try {
    artifacts.Remove(hash);
    return false;
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kFailedPrecondition) << error.what();
    return true;
  }
}

class JobPinsTest : public ::testing::Test {
 protected:
  JobPinsTest()
      : dir_(FreshDataDir()),
        artifacts_(dir_),
        cache_(artifacts_, clock_),
        queue_(dir_, clock_, kOneAttempt),
        state_(queue_, artifacts_, cache_, clock_, "", "", false) {}

  v1::SubmitJobResponse SubmitRenderWithMesh(int variant, v1::RenderMethod method) {
    mesh_ = PutQuad(artifacts_, variant);
    return SubmitJob(RenderOfMesh(mesh_, method), queue_, artifacts_, cache_);
  }
  bool MeshPinned() { return Pinned(artifacts_, mesh_); }

  // Leases render job `id` and completes it through the WorkerService call a worker
  // makes, with one uploaded frame; returns the frame's hash.
  std::string CompleteWithAFrame(const std::string& id, const std::string& frame_bytes) {
    const std::optional<JobLease> lease = queue_.Lease("w1");
    EXPECT_TRUE(lease.has_value() && lease->job.id() == id);
    const std::string frame = artifacts_.Put(frame_bytes);
    v1::CompleteJobRequest request;
    request.set_job_id(id);
    request.set_fencing_token(lease ? lease->token : 0);
    v1::ArtifactRef* artifact = request.add_artifacts();
    artifact->set_name("frame.png");
    artifact->set_sha256(frame);
    WorkerService workers(state_);
    grpc::ServerContext context;
    v1::CompleteJobResponse response;
    const grpc::Status status = workers.CompleteJob(&context, &request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return frame;
  }

  std::filesystem::path dir_;
  FakeClock clock_;
  ArtifactStore artifacts_;
  FabricCache cache_;
  JobQueue queue_;
  ServiceState state_;
  std::string mesh_;
};

TEST_F(JobPinsTest, ReleasedWhenTheLastAttemptsLeaseExpires) {
  const std::string id = SubmitRenderWithMesh(1, v1::RENDER_METHOD_REFERENCE).job().id();
  ASSERT_TRUE(queue_.Lease("w1").has_value());
  EXPECT_TRUE(MeshPinned());
  clock_.Advance(30'000);
  EXPECT_EQ(queue_.RequeueExpired(), 1);
  ASSERT_EQ(queue_.Get(id).state(), v1::JOB_STATE_FAILED);
  EXPECT_FALSE(MeshPinned());
}

TEST_F(JobPinsTest, ReleasedWhenADependencyFails) {
  const v1::SubmitJobResponse render = SubmitRenderWithMesh(2, v1::RENDER_METHOD_SVBRDF);
  ASSERT_EQ(render.dependencies_size(), 1);
  EXPECT_TRUE(MeshPinned());
  queue_.Cancel(render.dependencies(0).id());
  ASSERT_EQ(queue_.Get(render.job().id()).state(), v1::JOB_STATE_FAILED);
  EXPECT_FALSE(MeshPinned());
}

TEST_F(JobPinsTest, ReleasedWhenCancelled) {
  const std::string id = SubmitRenderWithMesh(3, v1::RENDER_METHOD_REFERENCE).job().id();
  EXPECT_TRUE(MeshPinned());
  EXPECT_EQ(queue_.Cancel(id).state(), v1::JOB_STATE_CANCELLED);
  EXPECT_FALSE(MeshPinned());
}

TEST_F(JobPinsTest, AFinishedRendersFramesAreKeptForTheRetentionThenReleased) {
  state_.result_retention_ms = 3'600'000;
  const std::string id = SubmitRenderWithMesh(5, v1::RENDER_METHOD_REFERENCE).job().id();
  const std::string frame = CompleteWithAFrame(id, "frame 5");
  ASSERT_EQ(queue_.Get(id).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_FALSE(MeshPinned());  // the job's inputs go when it ends, its frames stay
  EXPECT_EQ(artifacts_.PinOwners("result:"), std::vector<std::string>{JobResultPinOwner(id)});
  clock_.Advance(3'599'999);
  EXPECT_EQ(ReleaseExpiredResults(state_), 0);
  EXPECT_TRUE(Pinned(artifacts_, frame));
  clock_.Advance(1);
  EXPECT_EQ(ReleaseExpiredResults(state_), 1);
  EXPECT_TRUE(artifacts_.PinOwners("result:").empty());
  EXPECT_FALSE(Pinned(artifacts_, frame));  // an ordinary cache entry again (removed here)
}

TEST_F(JobPinsTest, AFrameTwoJobsRenderedIsKeptUntilTheLaterRetentionEnds) {
  state_.result_retention_ms = 1'000;
  const std::string first = SubmitRenderWithMesh(6, v1::RENDER_METHOD_REFERENCE).job().id();
  const std::string frame = CompleteWithAFrame(first, "the same frame");
  clock_.Advance(600);
  const std::string second = SubmitRenderWithMesh(7, v1::RENDER_METHOD_REFERENCE).job().id();
  EXPECT_EQ(CompleteWithAFrame(second, "the same frame"), frame);
  clock_.Advance(400);
  EXPECT_EQ(ReleaseExpiredResults(state_), 1);  // the first job's
  EXPECT_TRUE(Pinned(artifacts_, frame));
  clock_.Advance(600);
  EXPECT_EQ(ReleaseExpiredResults(state_), 1);
  EXPECT_FALSE(Pinned(artifacts_, frame));
}

TEST_F(JobPinsTest, NoRetentionPinsNoFrames) {
  state_.result_retention_ms = 0;
  const std::string id = SubmitRenderWithMesh(8, v1::RENDER_METHOD_REFERENCE).job().id();
  const std::string frame = CompleteWithAFrame(id, "frame 8");
  ASSERT_EQ(queue_.Get(id).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_FALSE(Pinned(artifacts_, frame));
}

TEST(JobPinsRestartTest, ReleasedWhenARestartVoidsTheLastAttemptsLease) {
  const auto dir = FreshDataDir();
  FakeClock clock;
  ArtifactStore artifacts(dir);
  FabricCache cache(artifacts, clock);
  const std::string mesh = PutQuad(artifacts, 4);
  std::string id;
  {
    JobQueue queue(dir, clock, kOneAttempt);
    ServiceState state(queue, artifacts, cache, clock, "", "", false);
    id = SubmitJob(RenderOfMesh(mesh, v1::RENDER_METHOD_REFERENCE), queue, artifacts, cache).job().id();
    ASSERT_TRUE(queue.Lease("w1").has_value());
  }  // the server stops with the job leased
  JobQueue queue(dir, clock, kOneAttempt);  // the restart voids the lease: the last attempt
  ASSERT_EQ(queue.Get(id).state(), v1::JOB_STATE_FAILED);
  EXPECT_TRUE(Pinned(artifacts, mesh));
  ServiceState state(queue, artifacts, cache, clock, "", "", false);  // told of the ending once it listens
  EXPECT_FALSE(Pinned(artifacts, mesh));
}

}  // namespace
}  // namespace loom::server
