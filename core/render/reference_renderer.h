#pragma once
// The `reference` frame renderer (DESIGN.md "Renderers", issue 5): the ground truth
// every accuracy figure is measured against. Cloth is the fabric's real tile
// geometry shell-mapped onto the surface and shaded exactly as acquisition shades
// its samples (core/acquire/yarn_radiance.h, core/acquire/indirect_light.h); other
// objects are Lambertian in their base colour. Ray traced on the CPU with Embree,
// many samples per pixel. Light units, ambient, background and camera are those of
// the svbrdf renderer (core/render/gpu_renderer.h), so frames compare directly.
//
// Pixels. render.reference_samples samples per pixel, averaged (a box filter over
// the pixel's area): with s = ⌊√n⌋, s² jittered samples on an s×s grid plus n − s²
// uniform ones. Each pixel draws from its own stream seeded by (render.seed, pixel
// index), so a frame is bit-identical whatever the thread count.
//
// Shell mapping. At a camera ray's hit on a cloth surface the surface frame is the
// svbrdf renderer's (interpolated normal n, tangent t along +u made perpendicular to
// n, bitangent b = (n × t)·handedness; seen from behind, n and b turn towards the
// viewer). Tile space maps to world space affinely:
//   world = P + (x − x_P)·s_u·t + (y − y_P)·s_v·b + z·s_u·n,   (x_P, y_P) = uv·repeat,
// with s_u = |∂P/∂u|/repeat_u and s_v = |∂P/∂v|/repeat_v from the triangle's UV
// Jacobian: the tile's z = 0 lies on the surface, its geometry spans
// [z_min, z_max]·s_u about it (height scales like the tangent direction). The ray
// enters the shell where tile z = z_max (just above the geometry), is traced in tile
// space through the infinitely repeated tile (PeriodicScene), and one that leaves the
// shell through a hole continues in world space behind the surface.
//
// What is exact and what is approximate.
// - Planes (any frame constant over the mesh): the mapping is the exact placement of
//   the repeated tile; rays, shadow rays and the hit geometry are exact. Shading is
//   evaluated in tile space with the directions mapped by the inverse of the
//   mapping and normalised: exact when s_u = s_v (a conformal map, e.g. the
//   built-in plane scaled (s, s) with repeat (r, r)); for a stretched tile it is the
//   unstretched fabric seen along the mapped directions.
// - Curved surfaces (spheres, cylinders, OBJ meshes): locally flat. Each camera ray
//   uses the frame at its macro hit for its whole walk through the shell, so the
//   shell is its tangent slab there; fine while the shell is thin against the
//   curvature radius: its error shrinks with the tile size, so it improves as t_N
//   grows (supported up to 64×64, the range). Silhouettes
//   are those of the macro surface (yarn standing above it at the rim is cut off).
// - Cloth is two-sided, as in the svbrdf renderer: a ray that meets the surface
//   from behind sees the shell mirrored through the surface (the turned frame), so
//   the fabric's top face faces it on either side.
// - Objects inside a shell (closer to the surface than the yarn's height) are not
//   seen through its holes: a ray that passes a hole continues from the surface.
// - Macro shadows (lights with casts_shadows, as in the svbrdf renderer; a point
//   light's shadow ray ends at the light): a yarn point's shadow ray leaves the
//   shell along the light's tile-space direction, then goes on in world space. Plain objects block it;
//   cloth blocks it where the light's ray through that cloth's shell meets yarn, so
//   holes let light through (lacy shadows; yarn that transmits still blocks it
//   there). Light from behind the surface (tile z < 0) reaches the yarn through
//   holes and through yarn that transmits, and leaves the shell through its bottom.
// - Indirect light (PrecomputeSettings.indirect_bounces of the object's precompute
//   settings, else the default): acquisition's per-vertex irradiance cache for the
//   light's tile-space direction. That direction is one per directional light when
//   the surface frame is constant (planes), and the cache is built for exactly those
//   directions, seen from the front and from behind. On curved surfaces and for
//   point lights it varies per point; there indirect light is left out (TODO:
//   quantise the direction and cache per cell).
// - Ambient: on yarn ambient · ρ_d (the diffuse part under a uniform environment,
//   unshadowed, as the svbrdf renderer's π·ρ of the fitted diffuse term); on plain
//   objects ambient · base colour.

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
