#version 450 core
// One yarn segment's shadow at a texel of the light's view (core/render/yarn_shadow_map.h):
// RGB T_y(d) of eq. 10, d the texel's distance from the centre line in yarn radii, for
// multiplicative blending; A the centre line's depth there, for min blending.

flat in vec3 v_start, v_end;
flat in float v_reach;
flat in float v_radius_map;
flat in int v_yarn;
in vec2 v_uv;

uniform sampler2D u_profiles;  // x: d / reach in [0, 1] over its width, y: yarn

layout(location = 0) out vec4 o_shadow;

void main() {
  vec2 ab = v_end.xy - v_start.xy;
  float u = dot(ab, ab) > 0.0 ? clamp(dot(v_uv - v_start.xy, ab) / dot(ab, ab), 0.0, 1.0) : 0.0;
  float d = distance(v_uv, v_start.xy + u * ab);
  if (d >= v_reach) discard;
  vec2 size = vec2(textureSize(u_profiles, 0));
  float x = d / v_reach * (size.x - 1.0) + 0.5;
  float t = texture(u_profiles, vec2(x / size.x, (float(v_yarn) + 0.5) / size.y)).r;
  o_shadow = vec4(vec3(t), mix(v_start.z, v_end.z, u));
}
