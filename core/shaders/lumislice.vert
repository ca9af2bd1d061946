#version 450 core
// A yarn segment of the lumislice renderer (core/render/lumislice_renderer.h): the box
// around it, reaching a section's extent beyond each end, whose back faces the
// fragment shader (lumislice.frag) marches from. 36 vertices a segment, no buffers:
// gl_VertexID picks the corner, gl_InstanceID the segment in drawing order.

#include "lumislice_segment.glsl"

uniform mat4 u_view_projection;

flat out int v_segment;
out vec3 v_position;

// The unit cube's triangles, counter-clockwise seen from outside; corner c is
// (c & 1, c >> 1 & 1, c >> 2 & 1).
const int kCubeCorners[36] = int[36](0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                                     2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6);

void main() {
  v_segment = gl_InstanceID;
  SegmentFrame frame = FrameOf(segments[gl_InstanceID]);
  int corner = kCubeCorners[gl_VertexID];
  vec3 unit = vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  float along = mix(-frame.reach, frame.length + frame.reach, unit.x);
  vec2 across = mix(vec2(-frame.reach), vec2(frame.reach), unit.yz);
  v_position = frame.origin + along * frame.t + across.x * frame.n + across.y * frame.b;
  gl_Position = u_view_projection * vec4(v_position, 1.0);
}
