#version 450 core
// A yarn segment of the lumislice renderer (core/render/lumislice_renderer.h): the box
// around it, reaching past each end as far as its joint's bisector does, whose back faces the
// fragment shader (lumislice.frag) marches from. Drawn indexed (kBoxIndices in
// lumislice_renderer.cpp) without vertex buffers: gl_VertexID is the corner,
// (c & 1, c >> 1 & 1, c >> 2 & 1) of the unit cube, gl_InstanceID the segment in
// drawing order.

#include "lumislice_segment.glsl"

uniform mat4 u_view_projection;

flat out int v_segment;
out vec3 v_position;

void main() {
  v_segment = gl_InstanceID;
  SegmentFrame frame = FrameOf(segments[gl_InstanceID]);
  int corner = gl_VertexID;
  vec3 unit = vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  // Beyond each end only as far as the bisector plane there leans out: reach·tan of
  // half the joint's bend.
  Segment s = segments[gl_InstanceID];
  float c0 = clamp(dot(s.start_plane.xyz, frame.t), 0.5, 1.0), c1 = clamp(dot(s.end_plane.xyz, frame.t), 0.5, 1.0);
  float pad0 = frame.reach * (sqrt(1.0 - c0 * c0) / c0 + 0.01), pad1 = frame.reach * (sqrt(1.0 - c1 * c1) / c1 + 0.01);
  float along = mix(-pad0, frame.length + pad1, unit.x);
  vec2 across = mix(vec2(-frame.reach), vec2(frame.reach), unit.yz);
  v_position = frame.origin + along * frame.t + across.x * frame.n + across.y * frame.b;
  gl_Position = u_view_projection * vec4(v_position, 1.0);
}
