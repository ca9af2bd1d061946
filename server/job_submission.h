#pragma once
// Turning a SubmitJobRequest into queue jobs, all checks first so that a rejected
// request stores nothing: specs validated (core/spec/validate.h: every issue, with
// field path and limit), meshes (a scene's objects', an animation's colliders')
// named by uploaded artifacts only (a client path is refused, never opened) and
// parsed, then for a svbrdf render each fabric the cache
// lacks gets its precompute (JobQueue::SubmitPrecomputeOnce: joined, never doubled)
// and the render depends on them.

#include <vector>

#include "core/render/scene_render.h"
#include "core/scene/mesh_sequence_cache.h"
#include "loom/v1/service.pb.h"
#include "server/store/artifact_store.h"
#include "server/store/fabric_cache.h"
#include "server/store/job_queue.h"

namespace loom::server {

// Error(kInvalidArgument) naming field and limit for a bad request; Error(kNotFound)
// for a mesh artifact the server lacks.
// `sequences` keeps the glTF sequences a render reads (a frame-range render reads
// one a frame).
v1::SubmitJobResponse SubmitJob(const v1::SubmitJobRequest& request, JobQueue& queue, ArtifactStore& artifacts,
                                FabricCache& cache, MeshSequenceCache* sequences = nullptr);

// The fabrics `render` shades with, as the worker looks them up (none for a render
// method that uses no fitted fabric).
std::vector<SceneFabric> RenderFabrics(const v1::RenderJob& render);

// The pin owner of a render's or an animation's mesh artifacts, held until the
// job ends.
std::string JobPinOwner(const std::string& job_id);

// The meshes of a job that name uploaded artifacts: a render's scene objects', an
// animation's mesh colliders'.
std::vector<const v1::MeshRef*> UploadedMeshes(const v1::Job& job);

// The precompute job that will put a scene's fabric into the cache: created, or
// joined if one is active (JobQueue::SubmitPrecomputeOnce).
v1::Job SubmitFabricPrecompute(const SceneFabric& fabric, int32_t priority, JobQueue& queue);

}  // namespace loom::server
