#version 450 core
// A yarn segment's band in a light's view (core/render/yarn_shadow_map.h): the
// rectangle around its centre line's image, its reach plus a texel wider each side.
// gl_VertexID is the corner (triangle strip), gl_InstanceID the segment.

#include "lumislice_segment.glsl"

uniform mat4 u_light_matrix;  // world → the map's [0,1]³
uniform float u_texel;        // one texel, in map units

flat out vec3 v_start, v_end;  // the centre line's ends in map space
flat out float v_reach;        // in map units
flat out float v_radius_map;   // the yarn's true radius in map units
flat out int v_yarn;
out vec2 v_uv;

void main() {
  Segment s = segments[gl_InstanceID];
  SegmentFrame f = FrameOf(s);
  // An orthographic light view: one world unit spans the same in x and y.
  float scale = length(vec3(u_light_matrix[0][0], u_light_matrix[1][0], u_light_matrix[2][0]));
  v_start = (u_light_matrix * vec4(s.start.xyz, 1.0)).xyz;
  v_end = (u_light_matrix * vec4(s.end.xyz, 1.0)).xyz;
  v_radius_map = f.radius * s.shading.x * scale;
  v_reach = u_extent[f.yarn] * v_radius_map;
  v_yarn = f.yarn;
  vec2 along = v_end.xy - v_start.xy;
  along = dot(along, along) > 1e-20 ? normalize(along) : vec2(1.0, 0.0);
  vec2 across = vec2(-along.y, along.x);
  float pad = v_reach + u_texel;
  int corner = gl_VertexID;
  vec2 base = (corner & 1) == 0 ? v_start.xy - along * pad : v_end.xy + along * pad;
  v_uv = base + across * ((corner & 2) == 0 ? -pad : pad);
  gl_Position = vec4(v_uv * 2.0 - 1.0, 0.0, 1.0);
}
