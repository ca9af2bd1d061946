#version 450 core
// A yarn segment's band in a light's view (core/render/yarn_shadow_map.h): the
// rectangle around its centre line's image, its reach plus a texel wider each side.
// gl_VertexID is the corner (triangle strip), gl_InstanceID the segment.

#include "lumislice_segment.glsl"

uniform mat4 u_light_matrix;  // world → the map's [0,1]³ (clip space: w the depth from a point light)
uniform float u_map_scale;    // map units per world unit across the view at w = 1
uniform float u_texel;        // one texel, in map units

flat out vec3 v_start, v_end;  // the centre line's ends in map space
flat out float v_reach;        // in map units
flat out float v_radius_map;   // the yarn's true radius in map units
flat out int v_yarn;
out vec2 v_uv;

void main() {
  Segment s = segments[gl_InstanceID];
  SegmentFrame f = FrameOf(s);
  vec4 start = u_light_matrix * vec4(s.start.xyz, 1.0);
  vec4 end = u_light_matrix * vec4(s.end.xyz, 1.0);
  if (start.w <= 0.0 || end.w <= 0.0) {  // beside or behind a point light: not in this face
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  v_start = start.xyz / start.w;
  v_end = end.xyz / end.w;
  // Across the light's view a world unit spans the same in x and y, less with depth
  // from a point light (the segment is short against that depth).
  v_radius_map = f.radius * s.shading.x * u_map_scale * 2.0 / (start.w + end.w);
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
