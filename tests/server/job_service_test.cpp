// The job service end to end in one process: client calls over loopback gRPC, the
// server's queue and cache, in-process or standalone workers rendering on llvmpipe.

#include <gmock/gmock.h>
#include <grpcpp/client_context.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <future>
#include <mutex>
#include <set>
#include <thread>

#include "core/fit/fabric_asset.h"
#include "core/image/image.h"
#include "core/methods/fabric_method.h"
#include "core/plan/precompute_plan.h"
#include "core/render/scene_render.h"
#include "core/scene/scene_geometry.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "rpc/artifact_transfer.h"
#include "rpc/channel.h"
#include "tests/server/service_fixture.h"
#include "tests/server/store/postgres_server.h"
#include "worker/worker_loop.h"

namespace loom::server {
namespace {

using ::testing::HasSubstr;

v1::Job WaitUntilEnded(client::JobClient& client, const std::string& id) {
  return client.Watch(id, [](const v1::JobEvent&) {});
}

TEST_F(ServiceTest, SecondServerOnAPortInUseFailsToStart) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  options.data_dir = data_dir_.string() + "-second";
  options.listen = server_->address();
  try {
    LoomServer second(options);
    FAIL() << "a second server started on " << options.listen;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnavailable);
    EXPECT_THAT(e.what(), HasSubstr("cannot listen on " + options.listen));
  }
  std::filesystem::remove_all(options.data_dir);
}

// Two servers on one PostgreSQL and one data directory (a shared volume) are one
// service: a job submitted through one is run by a worker of the other and watched
// through either; the fabric it made is in both one's cache.
TEST_F(ServiceTest, TwoServersOnOnePostgresStoreAreOneService) {
  ServerOptions options;
  options.local_workers = 0;
  options.store = FreshPostgresDatabase();
  StartServer(options);
  options.data_dir = data_dir_;
  options.listen = "127.0.0.1:0";
  options.lease_seconds = 3;
  LoomServer second(options);
  client::JobClient first_client = Client();
  client::JobClient second_client(rpc::MakeChannel(Channel(second, "")));

  const std::string id = first_client.Submit(PrecomputeRequest()).job().id();
  EXPECT_EQ(second_client.Get(id).state(), v1::JOB_STATE_QUEUED);
  std::future<v1::Job> watched_through_first =
      std::async(std::launch::async, [&] { return WaitUntilEnded(first_client, id); });
  worker::WorkerOptions worker_options;
  worker_options.lease_wait = std::chrono::milliseconds(500);
  worker::WorkerLoop worker(rpc::MakeChannel(Channel(second, "")), worker_options);
  std::thread thread([&worker] { worker.Run(); });
  const v1::Job ended = WaitUntilEnded(second_client, id);
  EXPECT_EQ(ended.state(), v1::JOB_STATE_SUCCEEDED) << ended.error();
  EXPECT_EQ(watched_through_first.get().state(), v1::JOB_STATE_SUCCEEDED);
  ASSERT_EQ(first_client.ListFabrics().fabrics_size(), 1);
  EXPECT_EQ(first_client.ListFabrics().fabrics(0).fabric_key(), ended.fabric_key());

  // A render through the first finds the fabric the second's worker made.
  const v1::SubmitJobResponse render = first_client.Submit(RenderRequest(TinyScene(32, 24)));
  EXPECT_EQ(render.dependencies_size(), 0);
  EXPECT_EQ(WaitUntilEnded(first_client, render.job().id()).state(), v1::JOB_STATE_SUCCEEDED);
  worker.Stop();
  thread.join();
  EXPECT_EQ(worker.completed_jobs(), 2u);
}

TEST_F(ServiceTest, AnUnreachableStoreIsUnavailableNamingTheFlag) {
  ServerOptions options;
  options.data_dir = std::filesystem::path(::testing::TempDir()) / "loom-unreachable-store";
  options.listen = "127.0.0.1:0";
  options.local_workers = 0;
  options.store = "host=/nonexistent port=1 dbname=loom connect_timeout=1";
  try {
    LoomServer bad(options);
    FAIL() << "a server started on an unreachable store";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnavailable);
    EXPECT_THAT(e.what(), HasSubstr("--store: PostgreSQL at /nonexistent:1/loom: cannot connect"));
  }
  std::filesystem::remove_all(options.data_dir);
}

TEST_F(ServiceTest, ABadResultRetentionIsRefusedNamingTheFlagAndItsLimits) {
  for (const double seconds : {-1.0, 366.0 * 86'400}) {
    ServerOptions options;
    options.data_dir = data_dir_.string() + "-retention";
    options.listen = "127.0.0.1:0";
    options.local_workers = 0;
    options.result_retention_seconds = seconds;
    try {
      LoomServer server(options);
      FAIL() << "a server started with --result-retention-seconds " << seconds;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      EXPECT_THAT(e.what(), HasSubstr("--result-retention-seconds: must be in [0, 31536000]"));
    }
    EXPECT_FALSE(std::filesystem::exists(options.data_dir));  // refused before anything is stored
  }
}

// A render whose fabric comes without precompute settings gets the least
// precompute that serves it (core/plan): the dependency fits what the plan chose,
// and the stored scene names those settings for the worker.
TEST_F(ServiceTest, RenderWithoutPrecomputeSettingsGetsThePlannedPrecompute) {
  ServerOptions options;
  options.local_workers = 0;  // nothing runs: the submission is what is checked
  StartServer(options);
  client::JobClient client = Client();
  v1::SceneSpec scene = TinyScene(128, 96);  // a knit at mid distance: the plan saves a lobe
  scene.mutable_objects(0)->mutable_fabric()->clear_precompute();
  const v1::SubmitJobResponse submitted = client.Submit(RenderRequest(scene));

  const v1::SceneSpec full = WithDefaults(scene);
  const ScenePlan plan =
      PlanScene(full, BuildSceneGeometry(full, FileMeshResolver({})), kDefaultErrorBudgetDb, StandardSweepVariations());
  ASSERT_EQ(plan.fabrics.size(), 1u);
  const v1::PrecomputeSettings& planned = plan.fabrics[0].settings;
  EXPECT_NE(planned.SerializeAsString(), WithDefaults(v1::PrecomputeSettings()).SerializeAsString())
      << "the plan should save something on this scene";
  ASSERT_EQ(submitted.dependencies_size(), 1);
  EXPECT_EQ(submitted.dependencies(0).precompute().settings().SerializeAsString(), planned.SerializeAsString());
  EXPECT_EQ(submitted.dependencies(0).fabric_key(), plan.fabrics[0].key);
  EXPECT_EQ(submitted.job().render().scene().objects(0).fabric().precompute().SerializeAsString(),
            planned.SerializeAsString());
  // GetJob names the planned fabric's key (the dashboard links a render to it).
  const v1::Job stored = client.Get(submitted.job().id());
  ASSERT_EQ(stored.fabric_keys_size(), 1);
  EXPECT_EQ(stored.fabric_keys(0), plan.fabrics[0].key);
}

// A lumislice render waits for no precompute: the worker builds the knit's lumislices
// itself, and nothing lands in the fabric cache.
TEST_F(ServiceTest, ALumisliceRenderRunsWithoutAPrecompute) {
  StartServer();
  client::JobClient client = Client();
  v1::SceneSpec scene = TinyScene(32, 24);
  scene.mutable_render()->set_method(v1::RENDER_METHOD_LUMISLICE);
  const v1::SubmitJobResponse submitted = client.Submit(RenderRequest(scene));
  EXPECT_EQ(submitted.dependencies_size(), 0);
  const v1::Job done = WaitUntilEnded(client, submitted.job().id());
  ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  EXPECT_EQ(done.result_artifacts_size(), 1);
  EXPECT_EQ(client.ListFabrics().fabrics_size(), 0);
  EXPECT_EQ(client.Get(done.id()).fabric_keys_size(), 0);
}

TEST_F(ServiceTest, PrecomputeRunsToSucceededAndCachesTheAsset) {
  StartServer();
  client::JobClient client = Client();
  const v1::SubmitJobResponse submitted = client.Submit(PrecomputeRequest());
  EXPECT_EQ(submitted.job().fabric_key(), FabricKey(KnitFabric(), TinySettings()));

  const v1::Job done = WaitUntilEnded(client, submitted.job().id());
  ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  EXPECT_EQ(done.result_artifacts_size(), static_cast<int>(TinyPrecomputeFiles().size()));
  const v1::GetFabricResponse fabric = client.GetFabric(done.fabric_key());
  std::set<std::string> names;
  for (const v1::ArtifactRef& file : fabric.fabric().files()) names.insert(file.name());
  EXPECT_EQ(names, TinyPrecomputeFiles());
  EXPECT_THAT(fabric.manifest_json(), HasSubstr(done.fabric_key()));
  EXPECT_EQ(client.ListFabrics().fabrics_size(), 1);
}

// What a worker's options.alive hears, and from which threads.
struct AliveStates {
  std::mutex mu;
  std::vector<std::string> states;
  std::set<std::thread::id> threads;
};

// A server whose one local worker records each alive state and the thread marking it.
class AliveServiceTest : public ServiceTest {
 protected:
  void SetUp() override {
    ServerOptions options;
    options.local_workers = 1;
    options.local_worker.alive = [alive = alive_](std::string_view state) {
      std::lock_guard lock(alive->mu);
      alive->states.emplace_back(state);
      alive->threads.insert(std::this_thread::get_id());
    };
    StartServer(options);
  }

  // Shared: the local worker goes on marking until the server stops, after the test body.
  const std::shared_ptr<AliveStates> alive_ = std::make_shared<AliveStates>();
};

TEST_F(AliveServiceTest, AWorkerMarksItselfAliveFromItsLoopThroughAPrecomputeAndARender) {
  const std::shared_ptr<AliveStates>& alive = alive_;
  client::JobClient client = Client();
  const v1::SubmitJobResponse submitted = client.Submit(RenderRequest(TinyScene(16, 12)));
  ASSERT_EQ(submitted.dependencies_size(), 1);
  const std::string precompute = submitted.dependencies(0).id();
  const std::string render = submitted.job().id();
  const v1::Job done = WaitUntilEnded(client, render);
  ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();

  std::lock_guard lock(alive->mu);
  const std::vector<std::string>& states = alive->states;
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states.front(), "started");
  const auto position = [&states](const std::string& state) {
    return std::find(states.begin(), states.end(), state) - states.begin();
  };
  const auto waiting = position("waiting for work");
  const auto precompute_started = position("job " + precompute + ": precompute");
  const auto acquisition = position("job " + precompute + ": acquisition");
  const auto fit = position("job " + precompute + ": svbrdf");
  const auto render_started = position("job " + render + ": render");
  const std::string all = ::testing::PrintToString(states);
  ASSERT_LT(render_started, std::ssize(states)) << all;  // every state was found, in this order:
  EXPECT_LT(waiting, precompute_started) << all;
  EXPECT_LT(precompute_started, acquisition) << all;
  EXPECT_LT(acquisition, fit) << all;
  EXPECT_LT(fit, render_started) << all;
  // Progress reports mark the stage, not every counter: the state changes a handful
  // of times per job (each change is a write of the alive file).
  std::vector<std::string> changes;
  std::unique_copy(states.begin(), states.end(), std::back_inserter(changes));
  EXPECT_LE(std::count_if(changes.begin(), changes.end(),
                          [&](const std::string& state) { return state.starts_with("job " + precompute + ":"); }),
            6)
      << ::testing::PrintToString(changes);
  // Only the loop's thread marks (never the heartbeat thread).
  EXPECT_EQ(alive->threads.size(), 1u);
}

// A reference render can take minutes and reports its pixel rows: the worker's
// liveness (and its lease's progress, which the server's stuck check reads) moves
// while it runs.
TEST_F(AliveServiceTest, AReferenceRenderReportsProgressWhileItRuns) {
  const std::shared_ptr<AliveStates>& alive = alive_;
  client::JobClient client = Client();
  v1::SceneSpec scene = TinyScene(16, 12);
  scene.mutable_render()->set_method(v1::RENDER_METHOD_REFERENCE);
  scene.mutable_render()->set_reference_samples(1);
  const std::string render = client.Submit(RenderRequest(scene)).job().id();
  const v1::Job done = WaitUntilEnded(client, render);
  ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  std::lock_guard lock(alive->mu);
  EXPECT_NE(std::find(alive->states.begin(), alive->states.end(), "job " + render + ": rendering"), alive->states.end())
      << ::testing::PrintToString(alive->states);
}

// Progress reaches WatchJob at every stage, not only with the lease's heartbeats
// (a third of the lease: 10 s here, longer than the whole precompute), and the last
// event says done (issue 22).
TEST_F(ServiceTest, ProgressReachesWatchersAtEveryStageWithoutWaitingForHeartbeats) {
  ServerOptions options;
  options.lease_seconds = 30;
  StartServer(options);
  client::JobClient client = Client();
  const std::string id = client.Submit(PrecomputeRequest()).job().id();
  std::set<std::string> running_stages;
  v1::JobEvent last;
  client.Watch(id, [&](const v1::JobEvent& event) {
    if (event.job().state() == v1::JOB_STATE_RUNNING) {
      running_stages.insert(event.job().progress().stage().substr(0, event.job().progress().stage().find(':')));
    }
    last = event;
  });
  EXPECT_EQ(last.job().state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_TRUE(running_stages.contains("acquisition")) << ::testing::PrintToString(running_stages);
  EXPECT_TRUE(running_stages.contains("svbrdf")) << ::testing::PrintToString(running_stages);
  EXPECT_EQ(last.job().progress().stage(), "done");
  EXPECT_EQ(last.job().progress().fraction(), 1.0);
}

TEST_F(ServiceTest, PrecomputeOfACachedFabricSucceedsAtOnceWithoutFittingAgain) {
  StartServer();
  client::JobClient client = Client();
  const v1::Job first = WaitUntilEnded(client, client.Submit(PrecomputeRequest()).job().id());
  ASSERT_EQ(first.state(), v1::JOB_STATE_SUCCEEDED) << first.error();

  const v1::Job again = client.Submit(PrecomputeRequest()).job();
  EXPECT_NE(again.id(), first.id());
  EXPECT_EQ(again.state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(again.attempts(), 0u);  // never leased
  EXPECT_EQ(again.fabric_key(), first.fabric_key());
  EXPECT_THAT(std::vector<std::string>(again.result_artifacts().begin(), again.result_artifacts().end()),
              ::testing::UnorderedElementsAreArray(first.result_artifacts()));
  std::string log;
  for (const std::string& line : client.Log(again.id())) log += line + "\n";
  EXPECT_THAT(log, HasSubstr("is already cached: nothing to compute")) << log;
  EXPECT_EQ(client.ListFabrics().fabrics_size(), 1);
}

// A yarn in the fibre-microflake model (issue 24) goes through the service like any
// other: its own cache entry, beside the Kajiya-Kay knit's, which for a yarn that
// passes light carries the back sheet a render worker reads back.
TEST_F(ServiceTest, AMicroflakeYarnPrecomputesThroughTheServiceUnderItsOwnKey) {
  StartServer();
  client::JobClient client = Client();
  v1::SubmitJobRequest request = PrecomputeRequest();
  v1::YarnSpec& yarn = *request.mutable_precompute()->mutable_fabric()->add_yarns();
  yarn.set_shading(v1::YARN_SHADING_MICROFLAKE);
  yarn.set_height_scale(0.5f);
  const v1::Job microflake = WaitUntilEnded(client, client.Submit(request).job().id());
  ASSERT_EQ(microflake.state(), v1::JOB_STATE_SUCCEEDED) << microflake.error();
  EXPECT_EQ(microflake.fabric_key(), FabricKey(request.precompute().fabric(), TinySettings()));
  const v1::Job kajiya_kay = WaitUntilEnded(client, client.Submit(PrecomputeRequest()).job().id());
  ASSERT_EQ(kajiya_kay.state(), v1::JOB_STATE_SUCCEEDED) << kajiya_kay.error();
  EXPECT_NE(kajiya_kay.fabric_key(), microflake.fabric_key());
  EXPECT_EQ(client.ListFabrics().fabrics_size(), 2);
  for (const v1::Job* job : {&microflake, &kajiya_kay}) {
    const auto asset = data_dir_ / ("asset-" + job->fabric_key());
    client.DownloadFabric(job->fabric_key(), asset);
    EXPECT_EQ(ReadAnyFabricAsset(asset)->back() != nullptr, job == &microflake);
  }
}

// Colour components (issue 24): a render of a fabric that differs from a cached one
// only in its yarn's albedos needs no precompute. Its frame is the core render of
// the edited scene from the cached asset, and not the original's frame.
TEST_F(ServiceTest, AColourEditRendersFromTheCachedAssetWithoutAPrecompute) {
  StartServer();
  client::JobClient client = Client();
  const auto scene_in = [](float red, float blue) {
    v1::SceneSpec scene = TinyScene();
    v1::FabricBinding& binding = *scene.mutable_objects(0)->mutable_fabric();
    binding.mutable_precompute()->set_colour_components(true);
    v1::Rgb& albedo = *binding.mutable_fabric()->add_yarns()->mutable_diffuse_albedo();
    albedo.set_r(red);
    albedo.set_g(0.3f);
    albedo.set_b(blue);
    return scene;
  };
  const auto render = [&](const v1::SceneSpec& scene, int expected_dependencies) {
    const v1::SubmitJobResponse submitted = client.Submit(RenderRequest(scene));
    EXPECT_EQ(submitted.dependencies_size(), expected_dependencies);
    const v1::Job done = WaitUntilEnded(client, submitted.job().id());
    EXPECT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
    return ReadImageBytes(client.Download(done.result_artifacts(0)), "served.exr");
  };
  const v1::SceneSpec red = scene_in(0.8f, 0.1f), blue = scene_in(0.1f, 0.8f);
  const Image red_frame = render(red, 1);
  const Image blue_frame = render(blue, 0);  // the red one's asset
  ASSERT_EQ(client.ListFabrics().fabrics_size(), 1);

  const v1::FabricBinding& binding = blue.objects(0).fabric();
  const std::string key = FabricKey(binding.fabric(), binding.precompute());
  const auto asset = data_dir_ / "asset-colour-components";
  client.DownloadFabric(key, asset);
  const std::unique_ptr<FabricAsset> fabric = ReadAnyFabricAsset(asset);
  ASSERT_TRUE(fabric->colour_channels().has_value());
  const auto context = gl::EglContext::Create();
  GpuRenderer renderer(*context);
  const v1::SceneSpec full = WithDefaults(blue);
  WriteImage(RenderScene(renderer, full, BuildSceneGeometry(full, FileMeshResolver(".")), {{key, fabric.get()}}).image,
             data_dir_ / "core.exr");
  const Image expected = ReadImage(data_dir_ / "core.exr");
  ASSERT_EQ(blue_frame.pixels.size(), expected.pixels.size());
  float max_difference = 0.0f;
  double red_sum = 0, blue_sum = 0, red_frame_red = 0;
  for (size_t i = 0; i < blue_frame.pixels.size(); ++i) {
    max_difference = std::max(max_difference, std::abs(blue_frame.pixels[i] - expected.pixels[i]));
    if (i % blue_frame.channels == 0) red_sum += blue_frame.pixels[i], red_frame_red += red_frame.pixels[i];
    if (i % blue_frame.channels == 2) blue_sum += blue_frame.pixels[i];
  }
  EXPECT_EQ(max_difference, 0.0f) << "served frame differs from the core render";
  EXPECT_GT(blue_sum, 2.0 * red_sum);
  EXPECT_GT(red_frame_red, 2.0 * red_sum);
}

// For every fabric method: the worker precomputes the method's asset, and the served
// frame equals the core render of the same scene from that cached asset.
TEST_F(ServiceTest, RenderedFrameEqualsTheCoreRenderOfTheSameSceneWithEveryMethod) {
  StartServer();
  client::JobClient client = Client();
  const auto context = gl::EglContext::Create();
  GpuRenderer renderer(*context);
  for (const v1::FabricMethod method :
       {v1::FABRIC_METHOD_SVBRDF, v1::FABRIC_METHOD_TABULATED, v1::FABRIC_METHOD_FACTORED, v1::FABRIC_METHOD_NEURAL}) {
    SCOPED_TRACE(v1::FabricMethod_Name(method));
    v1::SceneSpec scene = TinyScene();
    v1::PrecomputeSettings settings = TinySettings();
    settings.set_method(method);
    settings.mutable_neural()->set_steps(50);  // a tiny asset; the other methods ignore it
    for (v1::SceneObject& object : *scene.mutable_objects()) {
      if (object.has_fabric()) *object.mutable_fabric()->mutable_precompute() = settings;
    }
    const v1::SubmitJobResponse submitted = client.Submit(RenderRequest(scene));
    ASSERT_EQ(submitted.dependencies_size(), 1);  // the fabric was not cached
    ASSERT_EQ(submitted.job().depends_on(0), submitted.dependencies(0).id());
    const v1::Job done = WaitUntilEnded(client, submitted.job().id());
    ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
    ASSERT_EQ(done.result_artifacts_size(), 1);
    EXPECT_GT(done.timings().run_ms(), 0.0);  // the worker's own render time
    EXPECT_LT(done.timings().run_ms(),
              static_cast<double>(done.timings().finished_ms() - done.timings().submitted_ms() + 1));
    const Image served = ReadImageBytes(client.Download(done.result_artifacts(0)), "served.exr");

    // The core render of the same scene with the same cached asset, of this method.
    const auto asset = data_dir_ / ("asset-copy-" + v1::FabricMethod_Name(method));
    const std::string key = FabricKey(KnitFabric(), settings);
    client.DownloadFabric(key, asset);
    const std::unique_ptr<FabricAsset> fabric = ReadAnyFabricAsset(asset);
    EXPECT_EQ(&fabric->method(), &MethodOf(method));
    const v1::SceneSpec full = WithDefaults(scene);
    const Image core =
        RenderScene(renderer, full, BuildSceneGeometry(full, FileMeshResolver(".")), {{key, fabric.get()}}).image;
    const auto core_path = data_dir_ / "core.exr";
    WriteImage(core, core_path);  // the same half-float quantisation as the served frame
    const Image expected = ReadImage(core_path);

    ASSERT_EQ(served.width, 64);
    ASSERT_EQ(served.height, 48);
    ASSERT_EQ(served.pixels.size(), expected.pixels.size());
    float max_difference = 0.0f;
    for (size_t i = 0; i < served.pixels.size(); ++i) {
      max_difference = std::max(max_difference, std::abs(served.pixels[i] - expected.pixels[i]));
    }
    EXPECT_EQ(max_difference, 0.0f) << "served frame differs from the core render";
  }
}

TEST_F(ServiceTest, MissingOrWrongTokenIsUnauthenticatedAndStoresNothing) {
  ServerOptions options;
  options.client_token = "client-secret";
  options.worker_token = "worker-secret";
  options.local_workers = 0;
  StartServer(options);
  for (const std::string token : {"", "wrong", "worker-secret"}) {
    const grpc::Status status = RawSubmit(*RawStub(*server_, token), PrecomputeRequest());
    EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED) << "token '" << token << "'";
  }
  // Worker calls with the client token are refused as well.
  auto worker = v1::WorkerService::NewStub(rpc::MakeChannel(Channel(*server_, "client-secret")));
  grpc::ClientContext context;
  v1::LeaseJobRequest lease;
  lease.set_worker_id("w");
  v1::LeaseJobResponse leased;
  EXPECT_EQ(worker->LeaseJob(&context, lease, &leased).error_code(), grpc::StatusCode::UNAUTHENTICATED);

  client::JobClient client = Client("client-secret");
  EXPECT_EQ(JobCount(client), 0);
  EXPECT_EQ(client.ServerInfo().queued_jobs(), 0u);
}

TEST_F(ServiceTest, BadRequestsAreInvalidArgumentNamingTheFieldAndStoreNothing) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  auto stub = RawStub(*server_, "");
  auto expect_invalid = [&](const v1::SubmitJobRequest& request, const std::string& field) {
    const grpc::Status status = RawSubmit(*stub, request);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << field << ": " << status.error_message();
    EXPECT_THAT(status.error_message(), HasSubstr(field));
  };

  v1::SubmitJobRequest unknown = RenderRequest(TinyScene());
  v1::Camera& camera = *unknown.mutable_render()->mutable_scene()->mutable_camera();
  camera.GetReflection()->MutableUnknownFields(&camera)->AddVarint(99, 1);
  expect_invalid(unknown, "request.render.scene.camera: unknown field number 99");

  expect_invalid(RenderRequest(TinyScene(10000, 48)), "scene.render.width");

  v1::SubmitJobRequest bad_settings = PrecomputeRequest();
  bad_settings.mutable_precompute()->mutable_settings()->set_spatial_resolution(48);
  expect_invalid(bad_settings, "precompute.spatial_resolution");

  v1::SubmitJobRequest kajiya_kay_blend = PrecomputeRequest();
  kajiya_kay_blend.mutable_precompute()->mutable_fabric()->add_yarns()->set_lambert_blend(0.5f);
  expect_invalid(kajiya_kay_blend, "yarns[0].lambert_blend: only for shading YARN_SHADING_MICROFLAKE");

  v1::SceneSpec client_path = TinyScene();
  client_path.mutable_objects(0)->mutable_mesh()->set_obj_path("/etc/passwd");
  expect_invalid(RenderRequest(client_path), "scene.objects[0].mesh.obj_path");

  // An uploaded mesh that is not an OBJ: refused at submit, naming the object.
  const std::string garbage = "v 1 2\nf 1 2 3 4 5\nthis is not an OBJ\n";
  v1::UploadArtifactRequest::Header header;
  *header.mutable_artifact() = rpc::MakeArtifactRef("mesh.obj", garbage);
  rpc::UploadArtifact(*stub, header, garbage);
  v1::SceneSpec bad_mesh = TinyScene();
  bad_mesh.mutable_objects(0)->mutable_mesh()->set_artifact(header.artifact().sha256());
  expect_invalid(RenderRequest(bad_mesh), "cloth");

  v1::SceneSpec missing_mesh = TinyScene();
  missing_mesh.mutable_objects(0)->mutable_mesh()->set_artifact(std::string(64, 'a'));
  EXPECT_EQ(RawSubmit(*stub, RenderRequest(missing_mesh)).error_code(), grpc::StatusCode::NOT_FOUND);

  // Over the message cap: refused by gRPC before any handler runs.
  v1::SubmitJobRequest huge = RenderRequest(TinyScene());
  huge.mutable_render()->mutable_scene()->set_name(std::string(rpc::kMaxMessageBytes + 1, 'x'));
  EXPECT_EQ(RawSubmit(*stub, huge).error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);

  client::JobClient client = Client();
  EXPECT_EQ(JobCount(client), 0);
}

// The crash a client written from the protos found (issue 22): an uploaded OBJ
// whose face refers past the end of its vertex list, or before its start, or to a
// texture coordinate past the end, killed loom-server with SIGSEGV in SubmitJob.
TEST_F(ServiceTest, MeshesWithIndicesOutOfRangeAreRefusedAndTheServerGoesOn) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  auto stub = RawStub(*server_, "");
  client::JobClient client = Client();
  const v1::Job before = client.Submit(PrecomputeRequest()).job();
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
  for (const char* face :
       {"f 1/1 2/2 100000000/3", "f 1/1 2/2 -100000000/3", "f 1/1 2/2 3/100000000", "f 1/1 2/2 3/-5"}) {
    const std::string obj = head + face + "\n";
    v1::UploadArtifactRequest::Header header;
    *header.mutable_artifact() = rpc::MakeArtifactRef("mesh.obj", obj);
    rpc::UploadArtifact(*stub, header, obj);
    v1::SceneSpec scene = TinyScene();
    scene.mutable_objects(0)->mutable_mesh()->set_artifact(header.artifact().sha256());
    const grpc::Status status = RawSubmit(*stub, RenderRequest(scene));
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << face;
    EXPECT_THAT(status.error_message(), HasSubstr("scene.objects[0] (cloth): line 7: face refers to ")) << face;
    EXPECT_THAT(status.error_message(), HasSubstr("defined before it")) << face;
  }
  // Alive, and nothing it held was lost.
  EXPECT_EQ(client.Get(before.id()).state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(JobCount(client), 1);
}

TEST_F(ServiceTest, TwentyRendersOfOneUncachedFabricShareOnePrecompute) {
  ServerOptions options;
  options.local_workers = 0;  // everything is queued before any work starts
  StartServer(options);
  std::vector<std::future<v1::SubmitJobResponse>> submitted;
  for (int i = 0; i < 20; ++i) {
    submitted.push_back(
        std::async(std::launch::async, [this] { return Client().Submit(RenderRequest(TinyScene(32, 24))); }));
  }
  std::set<std::string> precomputes;
  std::vector<std::string> renders;
  for (auto& response : submitted) {
    const v1::SubmitJobResponse r = response.get();
    ASSERT_EQ(r.job().depends_on_size(), 1);
    precomputes.insert(r.job().depends_on(0));
    renders.push_back(r.job().id());
  }
  EXPECT_EQ(precomputes.size(), 1u);
  client::JobClient client = Client();
  EXPECT_EQ(JobCount(client, v1::JOB_KIND_PRECOMPUTE), 1);

  // A standalone worker over TCP runs all 21 jobs.
  worker::WorkerOptions worker_options;
  worker_options.lease_wait = std::chrono::milliseconds(500);
  worker::WorkerLoop worker(rpc::MakeChannel(Channel(*server_, "")), worker_options);
  std::thread thread([&worker] { worker.Run(); });
  for (const std::string& id : renders) EXPECT_EQ(WaitUntilEnded(client, id).state(), v1::JOB_STATE_SUCCEEDED);
  worker.Stop();
  thread.join();
  EXPECT_EQ(worker.completed_jobs(), 21u);
  EXPECT_EQ(JobCount(client, v1::JOB_KIND_PRECOMPUTE), 1);
}

TEST_F(ServiceTest, ARenderLeasedAfterItsFabricWasEvictedPrecomputesItAgain) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  client::JobClient client = Client();
  const auto run_worker_until_ended = [&](const std::string& id) {
    worker::WorkerOptions worker_options;
    worker_options.lease_wait = std::chrono::milliseconds(500);
    worker::WorkerLoop worker(rpc::MakeChannel(Channel(*server_, "")), worker_options);
    std::thread thread([&worker] { worker.Run(); });
    const v1::Job ended = WaitUntilEnded(client, id);
    worker.Stop();
    thread.join();
    return ended;
  };
  const v1::Job fabric = run_worker_until_ended(client.Submit(PrecomputeRequest()).job().id());
  ASSERT_EQ(fabric.state(), v1::JOB_STATE_SUCCEEDED) << fabric.error();

  // Submitted while the fabric is cached (no dependency), then the fabric goes.
  const v1::SubmitJobResponse render = client.Submit(RenderRequest(TinyScene(32, 24)));
  ASSERT_EQ(render.dependencies_size(), 0);
  client.DeleteFabric(fabric.fabric_key());

  const v1::Job done = run_worker_until_ended(render.job().id());
  EXPECT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  EXPECT_EQ(done.attempts(), 1u);  // the lease that found the fabric gone was given back
  ASSERT_EQ(done.depends_on_size(), 1);
  EXPECT_NE(done.depends_on(0), fabric.id());
  EXPECT_EQ(JobCount(client, v1::JOB_KIND_PRECOMPUTE), 2);
  EXPECT_EQ(client.ListFabrics().fabrics_size(), 1);
}

// A local worker whose first job's work throws `failure` (then works normally).
ServerOptions FailingFirstJob(std::function<void()> failure) {
  ServerOptions options;
  options.local_workers = 1;
  options.local_worker.before_job = [failure, failed = std::make_shared<std::atomic<bool>>(false)](const v1::Job&) {
    if (!failed->exchange(true)) failure();
  };
  return options;
}

TEST_F(ServiceTest, AJobFailingTransientlyOnTheOnlyWorkerSucceedsOnItsSecondAttempt) {
  StartServer(FailingFirstJob([] { throw std::runtime_error("injected: out of GPU memory"); }));
  client::JobClient client = Client();
  const v1::Job done = WaitUntilEnded(client, client.Submit(PrecomputeRequest()).job().id());
  EXPECT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED) << done.error();
  EXPECT_EQ(done.attempts(), 2u);
  std::string log;
  for (const std::string& line : client.Log(done.id())) log += line + "\n";
  EXPECT_THAT(log, HasSubstr("attempt 1 of 3 failed: internal error: injected: out of GPU memory")) << log;
}

TEST_F(ServiceTest, APermanentFailureEndsTheJobFailedAtOnceWithItsError) {
  StartServer(FailingFirstJob([] { throw Error(ErrorCode::kInvalidArgument, "injected: mesh does not parse"); }));
  client::JobClient client = Client();
  const v1::Job done = WaitUntilEnded(client, client.Submit(PrecomputeRequest()).job().id());
  EXPECT_EQ(done.state(), v1::JOB_STATE_FAILED);
  EXPECT_EQ(done.attempts(), 1u);
  EXPECT_THAT(done.error(), HasSubstr("injected: mesh does not parse"));
}

// A precompute big enough to still be running when a test interrupts it.
v1::SubmitJobRequest SlowPrecomputeRequest() {
  v1::SubmitJobRequest request = PrecomputeRequest();
  request.mutable_precompute()->mutable_settings()->set_spatial_resolution(32);
  request.mutable_precompute()->mutable_settings()->set_view_directions(64);
  request.mutable_precompute()->mutable_settings()->set_light_directions(64);
  return request;
}

TEST_F(ServiceTest, CancelOfARunningJobReachesTheWorker) {
  StartServer();
  client::JobClient client = Client();
  const std::string id = client.Submit(SlowPrecomputeRequest()).job().id();

  bool cancelled = false;
  const v1::Job ended = client.Watch(id, [&](const v1::JobEvent& event) {
    if (!cancelled && event.job().state() == v1::JOB_STATE_RUNNING) {
      EXPECT_TRUE(Client().Cancel(id).cancel_requested());
      cancelled = true;
    }
  });
  EXPECT_TRUE(cancelled);
  EXPECT_EQ(ended.state(), v1::JOB_STATE_CANCELLED);
  std::string log;
  for (const std::string& line : client.Log(id)) log += line + "\n";
  EXPECT_THAT(log, HasSubstr("cancelled on request")) << log;  // the worker's own report
  EXPECT_EQ(client.ListFabrics().fabrics_size(), 0);
}

TEST_F(ServiceTest, AStoppingWorkerHandsItsPrecomputeBack) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  client::JobClient client = Client();
  const std::string id = client.Submit(SlowPrecomputeRequest()).job().id();
  worker::WorkerLoop worker(rpc::MakeChannel(Channel(*server_, "")), worker::WorkerOptions{});
  std::thread thread([&worker] { worker.Run(); });

  // Once the job runs on the worker, stop the worker (what SIGTERM does in loom-worker).
  auto stub = RawStub(*server_, "");
  grpc::ClientContext context;
  v1::WatchJobRequest watch;
  watch.set_job_id(id);
  const auto reader = stub->WatchJob(&context, watch);
  v1::JobEvent event;
  while (reader->Read(&event) && event.job().state() != v1::JOB_STATE_RUNNING) {
  }
  ASSERT_EQ(event.job().state(), v1::JOB_STATE_RUNNING);
  context.TryCancel();
  reader->Finish();
  worker.Stop();
  thread.join();

  const v1::Job job = client.Get(id);
  EXPECT_EQ(job.state(), v1::JOB_STATE_QUEUED);  // requeued for another worker
  EXPECT_EQ(job.attempts(), 0u);                 // a hand-back uses up no attempt
  std::string log;
  for (const std::string& line : client.Log(id)) log += line + "\n";
  EXPECT_THAT(log, HasSubstr("handed back: worker worker is stopping")) << log;
  EXPECT_EQ(worker.completed_jobs(), 0u);
}

TEST_F(ServiceTest, ACancelledJobThatCompletesAnywayEndsCancelledWithNothingCached) {
  ServerOptions options;
  options.local_workers = 0;
  StartServer(options);
  client::JobClient client = Client();
  const std::string id = client.Submit(PrecomputeRequest()).job().id();

  // A worker (by hand) leases the job, the client cancels it, the worker completes it.
  auto worker = v1::WorkerService::NewStub(rpc::MakeChannel(Channel(*server_, "")));
  const std::string worker_id = RegisterWorker(*worker);
  v1::LeaseJobResponse leased;
  {
    grpc::ClientContext context;
    v1::LeaseJobRequest lease;
    lease.set_worker_id(worker_id);
    lease.set_wait_ms(5000);
    ASSERT_TRUE(worker->LeaseJob(&context, lease, &leased).ok());
    ASSERT_EQ(leased.job().id(), id);
  }
  EXPECT_TRUE(client.Cancel(id).cancel_requested());
  v1::CompleteJobRequest complete;
  complete.set_worker_id(worker_id);
  complete.set_job_id(id);
  complete.set_fencing_token(leased.fencing_token());
  for (const char* name : {"parameters.exr", "lut.exr", "manifest.json"}) {
    const std::string bytes = std::string("not really ") + name;
    v1::UploadArtifactRequest::Header header;
    *header.mutable_artifact() = rpc::MakeArtifactRef(name, bytes);
    header.set_job_id(id);
    header.set_fencing_token(leased.fencing_token());
    *complete.add_artifacts() = rpc::UploadArtifact(*worker, header, bytes);
  }
  grpc::ClientContext context;
  v1::CompleteJobResponse completed;
  ASSERT_TRUE(worker->CompleteJob(&context, complete, &completed).ok());
  EXPECT_EQ(client.Get(id).state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(client.ListFabrics().fabrics_size(), 0);
  // The same lease cannot report again.
  grpc::ClientContext again;
  EXPECT_EQ(worker->CompleteJob(&again, complete, &completed).error_code(), grpc::StatusCode::FAILED_PRECONDITION);
}

TEST_F(ServiceTest, ACorruptCachedFabricIsDetectedAndRecomputed) {
  StartServer();
  client::JobClient client = Client();
  const v1::Job first = WaitUntilEnded(client, client.Submit(PrecomputeRequest()).job().id());
  ASSERT_EQ(first.state(), v1::JOB_STATE_SUCCEEDED) << first.error();
  // Flip a byte of the cached lut.exr on disk.
  std::string lut_hash;
  const v1::GetFabricResponse cached = client.GetFabric(first.fabric_key());
  for (const v1::ArtifactRef& file : cached.fabric().files()) {
    if (file.name() == "lut.exr") lut_hash = file.sha256();
  }
  const auto path = data_dir_ / "artifacts" / lut_hash.substr(0, 2) / lut_hash;
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  std::string bytes = ReadFile(path);
  bytes[bytes.size() / 2] ^= 0x55;
  WriteFileAtomic(path, bytes);

  // A render needing the fabric finds it corrupt: evicted, precomputed again, rendered.
  const v1::SubmitJobResponse render = client.Submit(RenderRequest(TinyScene(32, 24)));
  ASSERT_EQ(render.dependencies_size(), 1);
  EXPECT_NE(render.dependencies(0).id(), first.id());
  EXPECT_EQ(WaitUntilEnded(client, render.job().id()).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(client.GetFabric(first.fabric_key()).fabric().files_size(),
            static_cast<int>(TinyPrecomputeFiles().size()));
}

}  // namespace
}  // namespace loom::server
