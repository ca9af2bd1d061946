// A render job's meshes stay pinned (kept from eviction) while the job may still
// run, and are released however it ends, including the endings that happen inside
// the queue: the last attempt's lease expiring, a failed dependency, a cancel.

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "server/job_submission.h"
#include "server/service_state.h"
#include "tests/server/store/store_test_util.h"
#include "tests/server/tiny_specs.h"

namespace loom::server {
namespace {

class JobPinsTest : public ::testing::Test {
 protected:
  JobPinsTest()
      : dir_(FreshDataDir()),
        artifacts_(dir_),
        cache_(artifacts_, clock_),
        queue_(dir_, clock_, JobQueueOptions{.lease_duration_ms = 30'000, .default_max_attempts = 1}),
        state_(queue_, artifacts_, cache_, clock_, "", "", false) {}

  // A render of TinyScene whose cloth is an uploaded quad (`variant` makes its
  // bytes, so its artifact, distinct); `method` svbrdf depends on a precompute.
  v1::SubmitJobResponse SubmitRenderWithMesh(int variant, v1::RenderMethod method) {
    mesh_ = artifacts_.Put("# quad " + std::to_string(variant) +
                           "\nv -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n");
    v1::SceneSpec scene = TinyScene(16, 16);
    scene.mutable_objects(0)->mutable_mesh()->set_artifact(mesh_);
    scene.mutable_render()->set_method(method);
    return SubmitJob(RenderRequest(scene), queue_, artifacts_, cache_);
  }

  bool MeshPinned() {
    try {
      artifacts_.Remove(mesh_);
      return false;
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ErrorCode::kFailedPrecondition) << error.what();
      return true;
    }
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

}  // namespace
}  // namespace loom::server
