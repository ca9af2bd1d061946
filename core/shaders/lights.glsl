// Scene lights and macro-scale shadows, shared by every surface shader.
// Light i: u_light_vector[i].w = 0 for directional lights (xyz = unit direction
// towards the light), 1 for point lights (xyz = position). u_light_radiance[i] is
// the irradiance at normal incidence (directional) or the intensity (point,
// irradiance = intensity / distance²). u_light_shadow[i] is the first layer of
// light i's shadow map in u_shadow_maps, or −1: a directional light's one layer, a
// point light's six cube faces (+x, −x, +y, −y, +z, −z; core/render/shadow_maps.h).

#include "constants.glsl"

const int kMaxLights = 16;
const int kMaxShadowLayers = 24;  // 4 lights × 6 faces

uniform int u_light_count;
uniform vec4 u_light_vector[kMaxLights];
uniform vec3 u_light_radiance[kMaxLights];
uniform int u_light_shadow[kMaxLights];
uniform mat4 u_shadow_matrix[kMaxShadowLayers];  // world → the layer's [0,1]³
uniform sampler2DArrayShadow u_shadow_maps;
uniform float u_shadow_bias;        // world units, directional layers
uniform float u_shadow_point_bias;  // per unit of distance from a point light
#ifdef LOOM_YARN_SHADOWS
// Per shadow map layer, the lumislice yarn over it (core/render/yarn_shadow_map.h): RGB
// the light the yarn lets through, A the nearest yarn's depth.
uniform sampler2DArray u_yarn_shadows;
#endif

// Unit direction towards light i from `position`, and the irradiance it brings
// at normal incidence there.
vec3 LightDirection(int i, vec3 position, out vec3 irradiance) {
  vec4 light = u_light_vector[i];
  if (light.w == 0.0) {
    irradiance = u_light_radiance[i];
    return light.xyz;
  }
  vec3 to_light = light.xyz - position;
  float distance2 = max(dot(to_light, to_light), 1e-8);
  irradiance = u_light_radiance[i] / distance2;
  return to_light * inversesqrt(distance2);
}

// Fraction of light i that reaches `position` (1 = lit), 3×3 PCF.
float LightVisibility(int i, vec3 position, vec3 normal) {
  int layer = u_light_shadow[i];
  if (layer < 0) return 1.0;
  float bias = u_shadow_bias;
  if (u_light_vector[i].w != 0.0) {
    vec3 d = position - u_light_vector[i].xyz;
    vec3 a = abs(d);
    layer += a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1) : a.y >= a.z ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5);
    bias = u_shadow_point_bias * length(d);
  }
  // Offset along the normal against acne on surfaces that face the light obliquely.
  vec4 p = u_shadow_matrix[layer] * vec4(position + normal * bias, 1.0);
  vec3 uvz = p.xyz / p.w;
  if (any(lessThan(uvz, vec3(0.0))) || any(greaterThan(uvz, vec3(1.0)))) return 1.0;
  vec2 texel = 1.0 / vec2(textureSize(u_shadow_maps, 0).xy);
  float lit = 0.0;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x)
      lit += texture(u_shadow_maps, vec4(uvz.xy + vec2(x, y) * texel, float(layer), uvz.z));
#ifdef LOOM_YARN_SHADOWS
  vec4 yarn = texture(u_yarn_shadows, vec3(uvz.xy, float(layer)));
  if (uvz.z > yarn.a) lit *= yarn.r;
#endif
  return lit / 9.0;
}
