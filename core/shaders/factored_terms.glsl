// The factored terms (core/methods/factored/factored_fabric.h): per texel and level K
// view tables a_k and K light tables b_k, four to an RGBA layer of two texture arrays,
// and their shape Σ_k a_k(v)·b_k(l) — the factored method's and the neural method's
// factored base. The view terms are interpolated between stored views by the texture
// filter, the light terms between the four stored lights around each light by hand
// (texelFetch: on llvmpipe far cheaper than the filtered fetch, docs/gpu.md).
// Requires LOOM_FABRIC_LIGHT_GRID's fragment fields (fabric_surface.glsl).

// The rank, compiled in (FactoredTermTextures::ShaderDefines): constant loop bounds,
// which llvmpipe unrolls. Every program the renderer makes defines it; without it (the
// file compiled on its own, as a test does) the bound is the largest rank.
#ifndef LOOM_FACTORED_RANK
#define LOOM_FACTORED_RANK 8  // core/spec/limits.h kMaxFactoredRank
#endif
const int kTermLayers = (LOOM_FACTORED_RANK + 3) / 4;  // four terms to a layer, zeros past the rank

uniform sampler2DArray u_fabric_view_terms;   // layer j, mip ℓ: a_4j…a_4j+3's (res_ℓ·k)² view atlas
uniform sampler2DArray u_fabric_light_terms;  // layer j, mip ℓ: b_4j…b_4j+3's (res_ℓ·k_l)² light atlas

// The view terms of texel `texel` of `level` for a view at `view_grid`.
void FetchViewTerms(ivec2 texel, int level, vec2 view_grid, out vec4 a[kTermLayers]) {
  float resolution = float(FabricResolution(level));
  float k = float(u_fabric_view_side);
  vec2 view_at = (vec2(texel) * k + view_grid + 0.5) / (resolution * k);
  for (int j = 0; j < kTermLayers; ++j) {
    a[j] = textureLod(u_fabric_view_terms, vec3(view_at, float(j)), float(level));
  }
}

// Σ_k a_k·b_k(l) of texel `texel` of `level` for a light at `light_grid`, not clamped.
float FactoredShape(vec4 a[kTermLayers], ivec2 texel, int level, vec2 light_grid) {
  ivec2 base = texel * u_fabric_light_side;  // the texel's block of the light atlas
  ivec2 g0 = ivec2(floor(light_grid));
  ivec2 g1 = min(g0 + 1, ivec2(u_fabric_light_side - 1));
  vec2 w = light_grid - vec2(g0);
  float sum = 0.0;
  for (int j = 0; j < kTermLayers; ++j) {
    vec4 b = mix(mix(texelFetch(u_fabric_light_terms, ivec3(base + g0, j), level),
                     texelFetch(u_fabric_light_terms, ivec3(base + ivec2(g1.x, g0.y), j), level), w.x),
                 mix(texelFetch(u_fabric_light_terms, ivec3(base + ivec2(g0.x, g1.y), j), level),
                     texelFetch(u_fabric_light_terms, ivec3(base + g1, j), level), w.x), w.y);
    sum += dot(a[j], b);
  }
  return sum;
}
