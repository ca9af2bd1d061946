#pragma once
// The lumislice renderer (render method LUMISLICE; the lumislice paper §5.2; issue 25):
// knit cloth drawn as volumetric yarn on the GPU. Each knit cloth's skeleton is placed
// on its mesh (core/render/knit_skeleton.h) and cut into segments; a segment's yarn is
// sampled at its level of detail's voxel spacing by a fragment shader that looks each
// sample up in its yarn's lumislice (core/methods/lumislice/lumislice_table.h) and
// composites front to back (core/shaders/lumislice.frag): the paper's slices, taken
// parallel to the viewport as its slice partitioning does, in one fragment per pixel
// and segment. Segments are blended back to front, sorted by the distance of their
// midpoints from the eye (ties by their place in the skeleton), so the frame does not
// depend on the order they are handed in. Light reaching a segment is dimmed by the
// yarns between it and the light (eq. 10, core/render/yarn_shadow.h) and by plain
// objects' shadow maps. Objects without a fabric are drawn first (opaque.frag, with
// their macro shadows and the yarn's, core/render/yarn_shadow_map.h); the yarn is cut
// where they stand in front.
//
// Level of detail (§5.2.2): a segment whose section spans m pixels takes the coarsest
// level of at least m voxels a side (the paper's rule) and at least 8×8, plus
// render.lod_bias levels rounded, and its samples are about that level's voxel apart.
// Far away a chain's points closer than a pixel are merged, and a yarn narrower than a
// pixel is drawn a pixel wide with its opacity scaled by its coverage
// (lumislice_segment.glsl).
// render.msaa_samples are rays a pixel on the nearest square grid (core/spec/limits.h
// LumisliceRayGrid): the frame rendered that many times larger and averaged.
// What is left out and measured: docs/lumislice.md.

#include <cstdint>
#include <list>
#include <map>
#include <string>
#include <memory>
#include <vector>

#include "core/gl/egl_context.h"
#include "core/gl/framebuffer.h"
#include "core/gl/shader_program.h"
#include "core/methods/lumislice/lumislice_table.h"
#include "core/render/gpu_renderer.h"
#include "core/render/knit_skeleton.h"
#include "core/render/shadow_maps.h"
#include "core/render/yarn_shadow_map.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/scene.pb.h"

namespace loom {

// A knit cloth object's yarns: its fabric's lumislice per FabricSpec.yarns index.
using YarnLumislices = std::vector<Lumislice>;

struct LumisliceFrame {
  RenderedFrame rendered;
  size_t segments = 0;  // drawn
  double slices = 0.0;  // the yarn's length over each segment's voxel spacing, summed
  std::vector<size_t> segments_per_level;
};

// Lumislices kept across frames, by serialised FabricSpec: at most `capacity` fabrics,
// the least recently used dropped first (a frame being rendered keeps its own).
class LumisliceCache {
 public:
  explicit LumisliceCache(size_t capacity) : capacity_(capacity) {}
  std::shared_ptr<const YarnLumislices> Find(const std::string& key);
  void Insert(const std::string& key, std::shared_ptr<const YarnLumislices> lumislices);

 private:
  size_t capacity_;
  std::list<std::pair<std::string, std::shared_ptr<const YarnLumislices>>> entries_;  // most recent first
};

// The lumislices of a scene's knit cloth, each distinct fabric once, found in `cache`
// or built (and then kept there); per_mesh[i] null for an object without a fabric.
// Error(kInvalidArgument) naming the object for cloth that is not knit.
struct SceneLumislices {
  std::map<std::string, std::shared_ptr<const YarnLumislices>> by_fabric;  // by serialised FabricSpec
  std::vector<const YarnLumislices*> per_mesh;
  size_t built = 0;      // fabrics built, not found in the cache
  double seconds = 0.0;  // to find or build them
};
SceneLumislices BuildSceneLumislices(const std::vector<SceneMesh>& meshes, const LumisliceSettings& settings,
                                     LumisliceCache* cache = nullptr);

class LumisliceRenderer {
 public:
  explicit LumisliceRenderer(gl::EglContext& context);
  ~LumisliceRenderer();

  // `scene` with defaults applied and validated; `meshes` = BuildSceneGeometry(scene);
  // `yarns[i]` the lumislices of meshes[i]'s knit fabric, or null for an object
  // without a fabric. Every lumislice has the same finest resolution. The segments are
  // handed to the sort in an order shuffled by `submission_seed` (0: the skeleton's).
  LumisliceFrame Render(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes,
                        const std::vector<const YarnLumislices*>& yarns, uint64_t submission_seed = 0);

 private:
  gl::EglContext& context_;
  gl::ShaderProgram yarn_program_;
  gl::ShaderProgram opaque_program_;
  std::unique_ptr<ShadowMaps> shadows_;
  std::unique_ptr<YarnShadowMap> yarn_shadow_map_;
};

}  // namespace loom
