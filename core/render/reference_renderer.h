#pragma once
// The `reference` frame renderer (DESIGN.md "Renderers"): the ground truth every
// accuracy figure is measured against. Cloth is the fabric's real tile geometry
// shell-mapped onto the surface and shaded exactly as acquisition shades its samples;
// other objects are Lambertian in their base colour. Ray traced on the CPU with
// Embree, render.reference_samples samples per pixel; a frame is bit-identical
// whatever the thread count. Light units, ambient, background and camera are the GPU
// renderer's, so frames compare directly. The shell mapping and what it does exactly
// and approximately: docs/reference.md.

#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "core/image/image.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/scene.pb.h"

namespace loom {

// Called on the calling thread as pixel rows finish (fraction in [0, 1]); what it
// throws abandons the render and is rethrown from Render.
using ReferenceProgress = std::function<void(double fraction, std::string_view stage)>;

struct ReferenceFrame {
  Image image;          // linear radiance, RGBA (alpha 1)
  double cpu_ms = 0.0;  // wall time of Render, fabric geometry and caches included
  uint64_t rays = 0;    // camera, shell, continuation and shadow rays (not the irradiance cache's)
};

class ReferenceRenderer {
 public:
  // 0 threads: every core.
  explicit ReferenceRenderer(unsigned threads = 0);

  // `scene` with defaults applied and validated; `meshes` = BuildSceneGeometry(scene).
  // Objects with a fabric are cloth. Throws Error(kInternal) if Embree fails.
  ReferenceFrame Render(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes,
                        const ReferenceProgress& progress = {}) const;

 private:
  unsigned threads_;
};

}  // namespace loom
