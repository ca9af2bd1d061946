#version 450 core
// Objects without a fabric: Lambertian in their base colour under the scene's
// lights with macro-scale shadows and ambient light. Output: linear radiance.

#include "lights.glsl"

in vec3 v_position;
in vec3 v_normal;

uniform vec3 u_base_colour;
uniform vec3 u_ambient;

layout(location = 0) out vec4 o_radiance;

void main() {
  vec3 n = normalize(v_normal);
  // Lit from either side: seen from behind, a surface turns its normal towards the viewer.
  if (!gl_FrontFacing) n = -n;
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
