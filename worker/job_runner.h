#pragma once
// What a render worker does with a leased job, without the RPC around it: a
// precompute becomes the fabric asset's files, a render becomes the frame file, an
// animation becomes its mesh sequence.
// Owns the worker's one EGL context (made once, reused for every job) and its
// svbrdf renderer (shader programs compiled once), and a scratch directory for the
// asset and image files core reads and writes: TMPDIR/loom-worker-<pid>-<n>, a
// job's files removed when its step ends (thrown or not), the directory when the
// runner is destroyed (a worker's every way out but SIGKILL or a crash). Making a
// runner first removes the scratch directories of worker processes that are gone.
//
// Not thread-safe: one job at a time, on the thread that made the runner (the
// context is current there).

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/gl/egl_context.h"
#include "core/precompute/fabric_precompute.h"
#include "core/render/lumislice_renderer.h"
#include "core/render/reference_renderer.h"
#include "core/render/scene_render.h"
#include "core/scene/mesh_sequence_cache.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/job.pb.h"

namespace loom::worker {

// One file of a job's result (or of a fabric asset it reads).
struct NamedFile {
  std::string name;  // "parameters.exr", "lut.exr", "manifest.json", "frame.png", "frame.exr", "sequence.glb"
  std::string bytes;
};

class JobRunner {
 public:
  // Makes the EGL context; Error(kUnavailable) listing every attempt when none
  // can be made.
  explicit JobRunner(const gl::ContextOptions& options);
  ~JobRunner();
  JobRunner(const JobRunner&) = delete;
  JobRunner& operator=(const JobRunner&) = delete;

  const gl::DeviceInfo& device() const { return context_->info(); }
  const std::filesystem::path& scratch_directory() const { return scratch_; }

  // The fabric asset of `job` (its method's, core/methods/fabric_method.h) as files, keyed
  // `fabric_key`, with its preview picture (core/render/fabric_preview.h) and its texel
  // pictures (core/methods/asset_pictures.h). `progress` is core's callback: throwing
  // from it cancels.
  std::vector<NamedFile> Precompute(const v1::PrecomputeJob& job, const std::string& fabric_key,
                                    const PrecomputeProgress& progress);

  // A fabric asset's files back into the asset (checksums verified).
  std::unique_ptr<FabricAsset> ReadAsset(const std::vector<NamedFile>& files);

  // The frame of `job`, encoded as its scene's format says (unspecified: PNG), by
  // the scene's method: the GPU renderer on the context, the lumislice renderer on it
  // (its knit fabrics' lumislices built for the job, or kept from one of the last
  // kLumisliceCacheFabrics fabrics' jobs), or the reference ray tracer.
  // `meshes` resolves uploaded mesh artifacts (a glTF sequence is read once and
  // its later frames taken from memory: core/scene/mesh_sequence_cache.h); for
  // the GPU, `assets` holds every fabric the scene names
  // (core/render/scene_render.h). `progress` hears of the reference's pixel rows
  // (an svbrdf frame takes too little time to report on); what it throws
  // abandons the render.
  NamedFile Render(const v1::RenderJob& job, const MeshTextResolver& meshes, const FabricAssets& assets,
                   const ReferenceProgress& progress = {});

  // The knit cloth of `job` simulated through its animation, as "sequence.glb"
  // (core/animate/cloth_sequence_io.h); the spec is validated first
  // (Error(kInvalidArgument) naming the field), its mesh colliders read through
  // `meshes`. `progress` hears of every frame; what it throws abandons the
  // simulation.
  NamedFile Animate(const v1::AnimateJob& job, const MeshTextResolver& meshes, const PrecomputeProgress& progress);

 private:
  static constexpr size_t kLumisliceCacheFabrics = 4;
  std::filesystem::path NewScratchPath(const std::string& stem);

  std::unique_ptr<gl::EglContext> context_;
  std::unique_ptr<GpuRenderer> renderer_;
  std::unique_ptr<LumisliceRenderer> lumislice_renderer_;   // made for the first lumislice job
  LumisliceCache lumislice_cache_{kLumisliceCacheFabrics};  // the last lumislice jobs' knit fabrics
  MeshSequenceCache sequences_;                             // the glTF sequences of the last frames' scenes
  std::filesystem::path scratch_;
  uint64_t next_scratch_ = 0;
};

}  // namespace loom::worker
