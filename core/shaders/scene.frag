#version 450 core
// Every scene object. Cloth carries a fitted fabric (fabric.glsl): per-fragment
// evaluation of the fitted BRDF array, alpha for holes. Other objects are
// Lambertian in their base colour. Both under the scene's lights with macro-scale
// shadows and ambient light. Output: linear radiance, premultiplied by the
// fabric's coverage alpha.

#include "fabric.glsl"

in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;

uniform vec3 u_base_colour;
uniform vec3 u_ambient;
uniform vec3 u_eye;
// Orthographic cameras look along one direction: towards the viewer, normalised.
uniform bool u_orthographic;
uniform vec3 u_towards_viewer;
uniform bool u_has_fabric;

layout(location = 0) out vec4 o_radiance;

// Below this a fabric fragment is a hole: less than one 8-bit step of coverage.
const float kMinCoverage = 1.0 / 256.0;

void main() {
  vec3 n = normalize(v_normal);
  // Meshes are lit from either side: seen from behind, a surface turns its frame
  // (the normal and with it the bitangent) towards the viewer.
  if (!gl_FrontFacing) n = -n;

  if (u_has_fabric) {
    vec3 t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));
    vec3 b = cross(n, t) * (v_tangent.w < 0.0 ? -1.0 : 1.0);
    vec3 view = u_orthographic ? u_towards_viewer : normalize(u_eye - v_position);
    vec4 shaded = ShadeFabric(v_uv, v_position, n, t, b, view, u_ambient);
    // A hole writes no depth, so cloth drawn later behind it still shows.
    if (shaded.a < kMinCoverage) discard;
    // Premultiplied: blended over what lies behind (SvbrdfRenderer draws cloth last).
    o_radiance = vec4(shaded.rgb * shaded.a, shaded.a);
    return;
  }

  vec3 radiance = u_ambient * u_base_colour;
  for (int i = 0; i < u_light_count; ++i) {
    vec3 irradiance;
    vec3 l = LightDirection(i, v_position, irradiance);
    float cosine = dot(n, l);
    if (cosine <= 0.0) continue;
    radiance += u_base_colour / kPi * irradiance * cosine * LightVisibility(i, v_position, n);
  }
  o_radiance = vec4(radiance, 1.0);
}
