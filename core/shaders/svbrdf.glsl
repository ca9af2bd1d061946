// The svbrdf method (core/methods/svbrdf/svbrdf_method.h): the fitted BRDF array
// (layout: core/render/fabric_textures.h) evaluated per texel — T(v) and alpha from
// the view atlas, f_1 from the lobes: Daubert 2001 eq. 1–2 with the paper's second
// mapping, surface → texel frame (the texel's fitted normal and tangent).

#include "lafortune.glsl"
#include "fabric_surface.glsl"

uniform sampler2DArray u_fabric_params;  // mip ℓ = fitted level ℓ
uniform int u_fabric_lobes;

// A texel of one level; its frame is in tile (= surface) space.
struct FabricTexel {
  LafortuneBrdf brdf;
  vec3 normal;
  vec3 tangent;
  vec3 bitangent;
  vec4 lut;  // T(v).rgb, alpha(v)
};

vec3 ToTexelFrame(FabricTexel t, vec3 d) { return vec3(dot(t.tangent, d), dot(t.bitangent, d), dot(t.normal, d)); }

// Texel `texel` of `level`, its T and alpha for the fragment's view.
FabricTexel FetchFabricTexel(ivec2 texel, int level, FabricFragment fragment) {
  FabricTexel t;
  t.brdf.rho = texelFetch(u_fabric_params, ivec3(texel, 0), level).rgb;
  t.normal = texelFetch(u_fabric_params, ivec3(texel, 1), level).xyz;
  t.tangent = texelFetch(u_fabric_params, ivec3(texel, 2), level).xyz;
  t.bitangent = cross(t.normal, t.tangent);
  // Only the fabric's lobes: EvaluateLafortune reads no others.
  for (int i = 0; i < u_fabric_lobes; ++i) {
    vec4 x = texelFetch(u_fabric_params, ivec3(texel, 3 + 3 * i), level);
    vec4 y = texelFetch(u_fabric_params, ivec3(texel, 4 + 3 * i), level);
    vec4 z = texelFetch(u_fabric_params, ivec3(texel, 5 + 3 * i), level);
    t.brdf.cx[i] = x.rgb;
    t.brdf.cy[i] = y.rgb;
    t.brdf.cz[i] = z.rgb;
    t.brdf.n[i] = vec3(x.a, y.a, z.a);
  }
  t.lut = FetchFabricView(texel, level, fragment.view_grid, fragment.beyond_ring);
  return t;
}

// Radiance (rgb) and coverage alpha of texel `texel` of `level` for the fragment:
// the shading every method defines (cloth.glsl calls it).
vec4 ShadeFabricTexel(ivec2 texel, int level, FabricFragment fragment) {
  FabricTexel t = FetchFabricTexel(texel, level, fragment);
  vec3 v = ToTexelFrame(t, fragment.view);
  // Ambient: a uniform environment over the diffuse part, π·ρ, through T (lobes left out).
  vec3 radiance = fragment.ambient * SheetRgb(t.lut.rgb * kPi * t.brdf.rho);
  for (int i = 0; i < u_light_count; ++i) {
    vec3 l = ToTexelFrame(t, fragment.light_direction[i]);
    radiance += fragment.light_irradiance[i] * SheetRgb(t.lut.rgb * EvaluateLafortune(t.brdf, u_fabric_lobes, l, v));
  }
  return vec4(radiance, t.lut.a);
}

