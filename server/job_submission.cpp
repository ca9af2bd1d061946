#include "server/job_submission.h"

#include <fmt/ranges.h>
#include <google/protobuf/unknown_field_set.h>
#include <spdlog/spdlog.h>

#include <set>

#include "core/animate/animation.h"
#include "core/plan/precompute_plan.h"
#include "core/render/scene_render.h"
#include "core/scene/scene_geometry.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "loom/v1/job_state.h"

namespace loom::server {
namespace {

constexpr size_t kMaxClientRequestId = 128;

void Invalid(const std::string& path, const std::string& message) {
  throw Error(ErrorCode::kInvalidArgument, path + ": " + message);
}

// Protobuf keeps fields it does not know (from a client built with a newer schema)
// as unknown fields; the server refuses them rather than silently ignore a setting.
void CheckNoUnknownFields(const google::protobuf::Message& message, const std::string& path) {
  const google::protobuf::Reflection& reflection = *message.GetReflection();
  const google::protobuf::UnknownFieldSet& unknown = reflection.GetUnknownFields(message);
  if (!unknown.empty()) Invalid(path, "unknown field number " + std::to_string(unknown.field(0).number()));
  std::vector<const google::protobuf::FieldDescriptor*> fields;
  reflection.ListFields(message, &fields);
  for (const google::protobuf::FieldDescriptor* field : fields) {
    if (field->cpp_type() != google::protobuf::FieldDescriptor::CPPTYPE_MESSAGE) continue;
    const std::string field_path = path + "." + field->name();
    if (!field->is_repeated()) {
      CheckNoUnknownFields(reflection.GetMessage(message, field), field_path);
      continue;
    }
    for (int i = 0; i < reflection.FieldSize(message, field); ++i) {
      CheckNoUnknownFields(reflection.GetRepeatedMessage(message, field, i),
                           field_path + "[" + std::to_string(i) + "]");
    }
  }
}

using FieldMeshes = std::vector<std::pair<std::string, const v1::MeshRef*>>;

// The meshes a render's scene objects and an animation's mesh colliders name,
// each with its field path in a submit request.
FieldMeshes PayloadMeshes(const v1::RenderJob& render, const v1::AnimateJob& animate) {
  FieldMeshes meshes;
  for (int i = 0; i < render.scene().objects_size(); ++i) {
    meshes.emplace_back("scene.objects[" + std::to_string(i) + "].mesh", &render.scene().objects(i).mesh());
  }
  for (int k = 0; k < animate.animation().colliders_size(); ++k) {
    const v1::ColliderSpec& collider = animate.animation().colliders(k);
    if (collider.has_mesh()) {
      meshes.emplace_back("animation.colliders[" + std::to_string(k) + "].mesh.mesh", &collider.mesh().mesh());
    }
  }
  return meshes;
}

// Meshes (each with its field path) must be built-in or uploaded artifacts (hashes
// already validated); returns the artifacts' hashes.
std::set<std::string> CheckMeshSources(const FieldMeshes& meshes, ArtifactStore& artifacts) {
  std::set<std::string> hashes;
  for (const auto& [path, ref] : meshes) {
    const v1::MeshRef& mesh = *ref;
    if (mesh.source_case() == v1::MeshRef::kObjPath || mesh.source_case() == v1::MeshRef::kGltfPath) {
      Invalid(path + (mesh.source_case() == v1::MeshRef::kObjPath ? ".obj_path" : ".gltf_path"),
              "the server never opens client paths; upload the mesh and name its artifact (loom render and loom "
              "animate do)");
    }
    if (mesh.source_case() != v1::MeshRef::kArtifact) continue;
    if (!artifacts.Has(mesh.artifact())) {
      throw Error(ErrorCode::kNotFound, path + ".artifact: no artifact " + mesh.artifact() +
                                            " on the server (upload it first: FindMissingArtifacts, UploadArtifact)");
    }
    hashes.insert(mesh.artifact());
  }
  return hashes;
}

// Holds a job's mesh artifacts until it ends (ServiceState releases them then). A
// job that ended before they were taken (at once, on a failed dependency, or
// raced to the end) would never release them: they are released here.
void PinUntilEnded(const std::set<std::string>& hashes, const std::string& job_id, JobQueue& queue,
                   ArtifactStore& artifacts) {
  const std::string owner = JobPinOwner(job_id);
  for (const std::string& hash : hashes) artifacts.Pin(hash, owner);
  if (IsTerminal(queue.Get(job_id).state())) artifacts.UnpinAll(owner);
}

v1::Job CheckedPrecompute(const v1::SubmitJobRequest& request) {
  const v1::PrecomputeJob& precompute = request.precompute();
  ThrowIfAny(Validate(precompute.fabric(), precompute.settings()));
  v1::Job job;
  job.set_kind(v1::JOB_KIND_PRECOMPUTE);
  *job.mutable_precompute() = precompute;
  job.set_fabric_key(FabricKey(precompute.fabric(), precompute.settings()));
  return job;
}

// A render's fabrics that come without precompute settings get the least precompute
// that serves the scene (core/plan, the default error budget), except a fabric
// already cached at the default settings: its cost is paid, and the defaults are
// at least as accurate. The stored scene names the settings, so the worker renders
// what was planned. `full` is `scene` with defaults applied, `meshes` its geometry.
// Adds to `cached` the keys found intact in the cache (a lookup verifies every
// file's checksum: the caller need not look them up again).
v1::SceneSpec WithPlannedPrecompute(const v1::SceneSpec& scene, const v1::SceneSpec& full,
                                    const std::vector<SceneMesh>& meshes, FabricCache& cache,
                                    std::set<std::string>& cached) {
  ScenePlan plan = PlanScene(full, meshes, kDefaultErrorBudgetDb, StandardSweepVariations());
  const v1::PrecomputeSettings defaults = WithDefaults(v1::PrecomputeSettings());
  for (FabricPlan& fabric : plan.fabrics) {
    if (fabric.explicit_settings) continue;
    const std::string default_key = FabricKey(fabric.fabric, defaults);
    if (cache.Get(default_key)) {
      cached.insert(default_key);
      fabric.settings = defaults;
      fabric.chosen = {"the defaults, cached already"};
    }
    spdlog::info("precompute planned for '{}': {}", fabric.objects.front(),
                 fabric.chosen.empty() ? "the defaults" : fmt::format("{}", fmt::join(fabric.chosen, ", ")));
    for (const std::string& reason : fabric.reasons) spdlog::debug("plan for '{}': {}", fabric.objects.front(), reason);
  }
  return ApplyPlan(scene, plan);
}

}  // namespace

std::vector<SceneFabric> RenderFabrics(const v1::RenderJob& render) {
  const v1::SceneSpec full = WithDefaults(render.scene());
  if (full.render().method() != v1::RENDER_METHOD_SVBRDF) return {};
  return SceneFabrics(full);
}

std::string JobPinOwner(const std::string& job_id) { return "job:" + job_id; }

std::vector<const v1::MeshRef*> UploadedMeshes(const v1::Job& job) {
  std::vector<const v1::MeshRef*> meshes;
  for (const auto& [path, mesh] : PayloadMeshes(job.render(), job.animate())) {
    if (mesh->source_case() == v1::MeshRef::kArtifact) meshes.push_back(mesh);
  }
  return meshes;
}

v1::Job SubmitFabricPrecompute(const SceneFabric& fabric, int32_t priority, JobQueue& queue) {
  v1::PrecomputeJob precompute;
  *precompute.mutable_fabric() = fabric.fabric;
  *precompute.mutable_settings() = fabric.settings;
  return queue.SubmitPrecomputeOnce(precompute, fabric.key, priority);
}

v1::SubmitJobResponse SubmitJob(const v1::SubmitJobRequest& request, JobQueue& queue, ArtifactStore& artifacts,
                                FabricCache& cache, MeshSequenceCache* sequences) {
  CheckNoUnknownFields(request, "request");
  if (request.client_request_id().size() > kMaxClientRequestId) {
    Invalid("client_request_id", std::to_string(request.client_request_id().size()) + " characters exceed " +
                                     std::to_string(kMaxClientRequestId));
  }
  v1::SubmitJobResponse response;
  if (request.payload_case() == v1::SubmitJobRequest::kPrecompute) {
    v1::Job job = CheckedPrecompute(request);
    job.set_priority(request.priority());
    job.set_client_request_id(request.client_request_id());
    // A fabric already cached is not fitted again: the answer is a job that
    // SUCCEEDED at once with the cached files, so that scripts and the CLI see the
    // usual submit-then-done, and the history shows the request.
    if (const std::optional<FabricEntry> cached = cache.Get(job.fabric_key())) {
      std::vector<std::string> files;
      for (const FabricFile& file : cached->files) files.push_back(file.hash);
      *response.mutable_job() = queue.SubmitDone(
          job, files, "fabric " + job.fabric_key() + " is already cached: nothing to compute (loom cache rm to refit)");
      spdlog::info("job {}: precompute of fabric {} answered from the cache", response.job().id(), job.fabric_key());
      return response;
    }
    // An explicit precompute joins one already running for the same fabric, unless
    // the client names its own request id (then the id decides what is a retry).
    if (request.client_request_id().empty()) {
      *response.mutable_job() = queue.SubmitPrecomputeOnce(job.precompute(), job.fabric_key(), request.priority());
    } else {
      *response.mutable_job() = queue.Submit(job);
    }
    spdlog::info("job {}: precompute of fabric {}", response.job().id(), response.job().fabric_key());
    return response;
  }
  if (request.payload_case() == v1::SubmitJobRequest::kAnimate) {
    const v1::AnimationSpec& animation = request.animate().animation();
    ThrowIfAny(Validate(animation));
    const std::set<std::string> meshes = CheckMeshSources(PayloadMeshes({}, request.animate()), artifacts);
    // Builds the mesh colliders now, so a mesh that is not closed is refused here
    // rather than failing on a worker.
    animate::BuildColliders(WithDefaults(animation), [&artifacts](const v1::MeshRef& mesh, const TextSink& consume) {
      artifacts.ReadInPieces(mesh.artifact(), consume);
    });
    v1::Job job;
    job.set_kind(v1::JOB_KIND_ANIMATE);
    *job.mutable_animate() = request.animate();
    job.set_priority(request.priority());
    job.set_client_request_id(request.client_request_id());
    *response.mutable_job() = queue.Submit(job);
    PinUntilEnded(meshes, response.job().id(), queue, artifacts);
    spdlog::info("job {}: animate '{}'", response.job().id(), request.animate().animation().name());
    return response;
  }
  if (request.payload_case() != v1::SubmitJobRequest::kRender) {
    Invalid("payload", "one of precompute, render or animate is required");
  }

  const v1::SceneSpec& scene = request.render().scene();
  ThrowIfAny(Validate(scene));
  const std::set<std::string> meshes = CheckMeshSources(PayloadMeshes(request.render(), {}), artifacts);
  v1::SceneSpec full = WithDefaults(scene);
  // Parses every mesh now (errors name the object), so a bad OBJ is refused here
  // rather than failing on a worker.
  const std::vector<SceneMesh> geometry =
      BuildSceneGeometry(
          full,
          [&artifacts](const v1::MeshRef& mesh, const TextSink& consume) {
            artifacts.ReadInPieces(mesh.artifact(), consume);
          },
          sequences);

  v1::Job job;
  job.set_kind(v1::JOB_KIND_RENDER);
  *job.mutable_render() = request.render();
  job.set_priority(request.priority());
  job.set_client_request_id(request.client_request_id());
  if (full.render().method() == v1::RENDER_METHOD_SVBRDF) {
    std::set<std::string> cached;
    *job.mutable_render()->mutable_scene() = WithPlannedPrecompute(scene, full, geometry, cache, cached);
    full = WithDefaults(job.render().scene());
    for (const SceneFabric& fabric : SceneFabrics(full)) {
      job.add_fabric_keys(fabric.key);
      if (cached.contains(fabric.key) || cache.Get(fabric.key)) continue;
      v1::Job dependency = SubmitFabricPrecompute(fabric, request.priority(), queue);
      job.add_depends_on(dependency.id());
      *response.add_dependencies() = std::move(dependency);
    }
  }
  *response.mutable_job() = queue.Submit(job);
  PinUntilEnded(meshes, response.job().id(), queue, artifacts);
  spdlog::info("job {}: render '{}' ({} fabric precompute(s) to wait for)", response.job().id(), scene.name(),
               response.dependencies_size());
  return response;
}

}  // namespace loom::server
