// The factored method (core/methods/factored/factored_fabric.h): per texel and
// level, A(v)/π ⊙ max(0, Σ_k a_k(v)·b_k(l)), A the view atlas's ambient response and
// the terms those of factored_terms.glsl. Directions in the tile (= surface) frame,
// as acquired. The view atlas holds A and coverage alpha.

#define LOOM_FABRIC_LIGHT_GRID
#include "fabric_surface.glsl"
#include "factored_terms.glsl"

vec4 ShadeFabricTexel(ivec2 texel, int level, FabricFragment fragment) {
  vec4 views = FetchFabricView(texel, level, fragment.view_grid, fragment.beyond_ring);
  vec4 a[kTermLayers];
  FetchViewTerms(texel, level, fragment.view_grid, a);
  vec3 lit = vec3(0.0);
  for (int i = 0; i < u_light_count; ++i) {
    float shape = FactoredShape(a, texel, level, fragment.light_grid[i]);
    lit += fragment.light_irradiance[i] * fragment.light_weight[i] * max(shape, 0.0);
  }
  // The shape is one number for every channel: mapping the gain maps the whole.
  return vec4(SheetRgb(views.rgb) * (fragment.ambient + lit / kPi), views.a);
}
