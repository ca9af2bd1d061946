#include "core/render/scene_render.h"

#include <memory>

#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/util/error.h"

namespace loom {

std::vector<SceneFabric> SceneFabrics(const v1::SceneSpec& scene) {
  const v1::SceneSpec full = WithDefaults(scene);
  std::vector<SceneFabric> fabrics;
  for (const v1::SceneObject& object : full.objects()) {
    if (!object.has_fabric()) continue;
    const v1::FabricBinding& binding = object.fabric();
    std::string key = FabricKey(binding.fabric(), binding.precompute());
    bool seen = false;
    for (const SceneFabric& fabric : fabrics) seen = seen || fabric.key == key;
    if (!seen) fabrics.push_back({std::move(key), binding.fabric(), binding.precompute()});
  }
  return fabrics;
}

RenderedFrame RenderScene(GpuRenderer& renderer, const v1::SceneSpec& scene,
                          const std::vector<SceneMesh>& meshes, const FabricAssets& assets) {
  std::map<std::string, std::unique_ptr<GpuFabric>> uploads;
  std::vector<const GpuFabric*> fabrics(meshes.size(), nullptr);
  for (size_t i = 0; i < meshes.size(); ++i) {
    const v1::SceneObject& object = *meshes[i].object;
    if (!object.has_fabric()) continue;
    const v1::FabricBinding& binding = object.fabric();
    const std::string key = FabricKey(binding.fabric(), binding.precompute());
    auto& uploaded = uploads[key];
    if (!uploaded) {
      const auto asset = assets.find(key);
      if (asset == assets.end() || asset->second == nullptr) {
        throw Error(ErrorCode::kFailedPrecondition,
                    "object '" + object.name() + "': fabric " + key + " is not precomputed");
      }
      uploaded = UploadSheets(*asset->second, binding.precompute().half_float());
    }
    fabrics[i] = uploaded.get();
  }
  return renderer.Render(scene, meshes, fabrics);
}

}  // namespace loom
