#pragma once
// A fabric's preview picture (the dashboard's fabric page; issue 27): a sphere
// covered with the fabric, seen from the front under one light and a little ambient
// light, shaded by the fabric's own method from its fitted asset. The worker renders
// it after every precompute and stores it beside the asset as kFabricPreviewFile.

#include "core/image/image.h"
#include "core/methods/fabric_method.h"
#include "core/render/gpu_renderer.h"
#include "loom/v1/scene.pb.h"

namespace loom {

inline constexpr char kFabricPreviewFile[] = "preview.png";
inline constexpr int kFabricPreviewPixels = 256;

// The preview's scene (defaults not applied), kFabricPreviewPixels square, PNG.
v1::SceneSpec FabricPreviewScene(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings);

// The preview of `asset`, the fabric `fabric` built with `settings`, rendered by
// `renderer` on its context (current on the calling thread): linear RGBA.
Image RenderFabricPreview(GpuRenderer& renderer, const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings,
                          const FabricAsset& asset);

}  // namespace loom
