// The factored method (core/methods/factored/factored_fabric.h): per texel and
// level, A(v)/π ⊙ max(0, Σ_k a_k(v)·b_k(l)), A the view atlas's ambient response,
// the view tables interpolated between the stored views by the texture filter and the
// light tables between the four stored lights around each light by hand (texelFetch:
// on llvmpipe far cheaper than the filtered fetch, docs/gpu.md). Directions in the
// tile (= surface) frame, as acquired. The view atlas holds A and coverage alpha.

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
  float k = float(u_fabric_view_side);
  vec2 view_at = (vec2(texel) * k + fragment.view_grid + 0.5) / (resolution * k);
  vec4 a[kLayers];
  for (int j = 0; j < kLayers; ++j) {
    a[j] = textureLod(u_fabric_view_terms, vec3(view_at, float(j)), float(level));
  }
  ivec2 base = texel * u_fabric_light_side;  // the texel's block of the light atlas
  vec3 lit = vec3(0.0);
  for (int i = 0; i < u_light_count; ++i) {
    vec2 g = fragment.light_grid[i];
    ivec2 g0 = ivec2(floor(g));
    ivec2 g1 = min(g0 + 1, ivec2(u_fabric_light_side - 1));
    vec2 w = g - vec2(g0);
    float sum = 0.0;
    for (int j = 0; j < kLayers; ++j) {
      vec4 b = mix(mix(texelFetch(u_fabric_light_terms, ivec3(base + g0, j), level),
                       texelFetch(u_fabric_light_terms, ivec3(base + ivec2(g1.x, g0.y), j), level), w.x),
                   mix(texelFetch(u_fabric_light_terms, ivec3(base + ivec2(g0.x, g1.y), j), level),
                       texelFetch(u_fabric_light_terms, ivec3(base + g1, j), level), w.x), w.y);
      sum += dot(a[j], b);
    }
    lit += fragment.light_irradiance[i] * fragment.light_weight[i] * max(sum, 0.0);
  }
  return vec4(views.rgb * (fragment.ambient + lit / kPi), views.a);
}
