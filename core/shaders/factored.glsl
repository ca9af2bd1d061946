// The factored method (core/methods/factored/factored_fabric.h): per texel and
// level, Σ_k A_k(v)·B_k(l), the view tables interpolated between the stored views
// and the light tables between the stored lights by the texture filter, the sum
// clamped at 0. Directions in the tile (= surface) frame, as acquired. The view
// atlas holds the ambient response and coverage alpha.

#define LOOM_FABRIC_LIGHT_GRID
#include "fabric_surface.glsl"

// The asset's rank, compiled in (FactoredTextures::ShaderDefines): constant loop
// bounds, which llvmpipe unrolls. Every program the renderer makes defines it; without
// it (the file compiled on its own, as a test does) the bound is the largest rank.
#ifndef LOOM_FACTORED_RANK
#define LOOM_FACTORED_RANK 8  // core/spec/limits.h kMaxFactoredRank
#endif
const int kRank = LOOM_FACTORED_RANK;

uniform sampler2DArray u_fabric_view_terms;   // layer k, mip ℓ: A_k's (res_ℓ·k)² view atlas
uniform sampler2DArray u_fabric_light_terms;  // layer k, mip ℓ: B_k's (res_ℓ·k_l)² light atlas

vec4 ShadeFabricTexel(ivec2 texel, int level, FabricFragment fragment) {
  vec4 views = FetchFabricView(texel, level, fragment.view_grid, fragment.beyond_ring);
  vec3 radiance = fragment.ambient * views.rgb;
  float resolution = float(FabricResolution(level));
  float k = float(u_fabric_view_side), kl = float(u_fabric_light_side);
  vec2 view_at = (vec2(texel) * k + fragment.view_grid + 0.5) / (resolution * k);
  vec3 a[kRank];
  for (int t = 0; t < kRank; ++t) {
    a[t] = textureLod(u_fabric_view_terms, vec3(view_at, float(t)), float(level)).rgb;
  }
  for (int i = 0; i < u_light_count; ++i) {
    vec2 light_at = (vec2(texel) * kl + fragment.light_grid[i] + 0.5) / (resolution * kl);
    vec3 sum = vec3(0.0);
    for (int t = 0; t < kRank; ++t) {
      sum += a[t] * textureLod(u_fabric_light_terms, vec3(light_at, float(t)), float(level)).rgb;
    }
    radiance += fragment.light_irradiance[i] * fragment.light_weight[i] * max(sum, vec3(0.0));
  }
  return vec4(radiance, views.a);
}
