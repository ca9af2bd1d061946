#pragma once
// A scene rendered on the GPU from fabric assets that are already built: the one
// piece shared by `loom-lab render` (which builds each fabric in-process) and the
// render worker (which reads them from cached assets), so both make the same frame
// from the same assets.

#include <map>
#include <string>
#include <vector>

#include "core/methods/fabric_method.h"
#include "core/render/gpu_renderer.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {

// One fabric a scene needs: what it is, how it is precomputed, and its cache key.
struct SceneFabric {
  std::string key;  // FabricKey(fabric, settings)
  v1::FabricSpec fabric;
  v1::PrecomputeSettings settings;
};

// The distinct fabrics of `scene` (defaults applied), in order of first use.
// Objects sharing a fabric and settings share one entry.
std::vector<SceneFabric> SceneFabrics(const v1::SceneSpec& scene);

// Fabric assets by cache key; the caller owns them.
using FabricAssets = std::map<std::string, const FabricAsset*>;

// Uploads each distinct fabric once and renders with `renderer` on its context
// (current on the calling thread). `scene` with defaults applied and validated,
// `meshes` = BuildSceneGeometry(scene). Throws Error(kFailedPrecondition) naming
// the object whose fabric is not in `assets`.
RenderedFrame RenderScene(GpuRenderer& renderer, const v1::SceneSpec& scene,
                          const std::vector<SceneMesh>& meshes, const FabricAssets& assets);

}  // namespace loom
