// The factored method (core/methods/factored/factored_fabric.h): per texel and
// level, A(v)/π ⊙ max(0, Σ_k a_k(v)·b_k(l)), A the view atlas's ambient response,
// the view tables interpolated between the stored views and the light tables between
// the stored lights by the texture filter. Directions in the tile (= surface) frame,
// as acquired. The view atlas holds A and coverage alpha.

#define LOOM_FABRIC_LIGHT_GRID
#include "fabric_surface.glsl"

// The asset's rank, compiled in (FactoredTextures::ShaderDefines): constant loop
// bounds, which llvmpipe unrolls. Every program the renderer makes defines it; without
// it (the file compiled on its own, as a test does) the bound is the largest rank.
#ifndef LOOM_FACTORED_RANK
#define LOOM_FACTORED_RANK 8  // core/spec/limits.h kMaxFactoredRank
#endif
const int kLayers = (LOOM_FACTORED_RANK + 3) / 4;  // four terms to a layer, zeros past the rank

uniform sampler2DArray u_fabric_view_terms;   // layer j, mip ℓ: a_4j…a_4j+3's (res_ℓ·k)² view atlas
uniform sampler2DArray u_fabric_light_terms;  // layer j, mip ℓ: b_4j…b_4j+3's (res_ℓ·k_l)² light atlas

vec4 ShadeFabricTexel(ivec2 texel, int level, FabricFragment fragment) {
  vec4 views = FetchFabricView(texel, level, fragment.view_grid, fragment.beyond_ring);
  float resolution = float(FabricResolution(level));
  float k = float(u_fabric_view_side), kl = float(u_fabric_light_side);
  vec2 view_at = (vec2(texel) * k + fragment.view_grid + 0.5) / (resolution * k);
  vec4 a[kLayers];
  for (int j = 0; j < kLayers; ++j) {
    a[j] = textureLod(u_fabric_view_terms, vec3(view_at, float(j)), float(level));
  }
  vec3 lit = vec3(0.0);
  for (int i = 0; i < u_light_count; ++i) {
    vec2 light_at = (vec2(texel) * kl + fragment.light_grid[i] + 0.5) / (resolution * kl);
    float sum = 0.0;
    for (int j = 0; j < kLayers; ++j) {
      sum += dot(a[j], textureLod(u_fabric_light_terms, vec3(light_at, float(j)), float(level)));
    }
    lit += fragment.light_irradiance[i] * fragment.light_weight[i] * max(sum, 0.0);
  }
  return vec4(views.rgb * (fragment.ambient + lit / kPi), views.a);
}
