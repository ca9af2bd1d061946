// The tabulated method (core/methods/tabulated/tabulated_fabric.h): each texel's
// acquired radiance per (view, light), pooled per level, interpolated bilinearly
// between the four stored views around the fragment's view and, by the texture
// filter, the four stored lights around each light. Directions are in the tile
// (= surface) frame, as acquired: no texel frame. The view atlas holds the ambient
// response (radiance under a uniform unit environment) and coverage alpha.

#define LOOM_FABRIC_LIGHT_GRID
#include "fabric_surface.glsl"

// mip ℓ: a (res_ℓ·k·k_l)² atlas: texel (x, y), view (vc, vr), light (lc, lr) at
// ((x·k + vc)·k_l + lc, (y·k + vr)·k_l + lr); rgb radiance per unit irradiance.
uniform sampler2D u_fabric_table;

// The radiance of stored view `view` of a texel for a light at `light_grid`,
// bilinear between the stored lights inside the view's k_l×k_l block.
vec3 FetchTabulated(ivec2 texel, int level, ivec2 view, vec2 light_grid) {
  float k = float(u_fabric_view_side), kl = float(u_fabric_light_side);
  vec2 atlas = ((vec2(texel) * k + vec2(view)) * kl + light_grid + 0.5) / (float(FabricResolution(level)) * k * kl);
  return textureLod(u_fabric_table, atlas, float(level)).rgb;
}

vec4 ShadeFabricTexel(ivec2 texel, int level, FabricFragment fragment) {
  vec4 views = FetchFabricView(texel, level, fragment.view_grid, fragment.beyond_ring);
  vec3 radiance = fragment.ambient * SheetRgb(views.rgb);
  ivec2 v0 = ivec2(floor(fragment.view_grid));
  ivec2 v1 = min(v0 + 1, ivec2(u_fabric_view_side - 1));
  vec2 w = fragment.view_grid - vec2(v0);
  for (int i = 0; i < u_light_count; ++i) {
    vec2 g = fragment.light_grid[i];
    vec3 bottom = mix(FetchTabulated(texel, level, v0, g), FetchTabulated(texel, level, ivec2(v1.x, v0.y), g), w.x);
    vec3 top = mix(FetchTabulated(texel, level, ivec2(v0.x, v1.y), g), FetchTabulated(texel, level, v1, g), w.x);
    radiance += fragment.light_irradiance[i] * fragment.light_weight[i] * SheetRgb(mix(bottom, top, w.y));
  }
  return vec4(radiance, views.a);
}
