#pragma once
// The small specs the service, worker and client tests submit: a precompute small
// enough to run in a second or two on llvmpipe, and a small scene that uses it.

#include <cstdint>
#include <set>
#include <string>

#include "loom/v1/service.pb.h"

namespace loom::server {

// 8×8 texels, 16 views × 16 lights, 1 lobe, no indirect light, 1 sub-sample.
v1::PrecomputeSettings TinySettings();
// The standard knit.
v1::FabricSpec KnitFabric();
// A knit plane seen at 45°, one shadowing light, `width`×`height` pixels, with
// TinySettings; EXR output.
v1::SceneSpec TinyScene(uint32_t width = 64, uint32_t height = 48);

v1::SubmitJobRequest PrecomputeRequest();
// The files a worker's precompute of TinySettings yields: the svbrdf asset's, the
// preview, and the pictures of each of its 4 levels with their list.
std::set<std::string> TinyPrecomputeFiles();
v1::SubmitJobRequest RenderRequest(const v1::SceneSpec& scene);

}  // namespace loom::server
