#version 450 core
// Every scene object: world-space position, normal, tangent frame and uv for the
// lighting in the cloth programs (cloth.glsl) and opaque.frag. Meshes arrive in world space
// (core/scene/scene_geometry.h).

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_tangent;  // xyz along +u, w: handedness of +v

uniform mat4 u_view_projection;

out vec3 v_position;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;
// The same depth in every program: a cloth's back sheet is drawn over its front with
// an equal-depth test (GpuRenderer).
invariant gl_Position;

void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_tangent = a_tangent;
  v_uv = a_uv;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
