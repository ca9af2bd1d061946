#version 450 core
// Cloth: per-fragment evaluation of the fitted BRDF array (fabric.glsl) under the
// scene's lights with macro-scale shadows and ambient light, alpha for holes.
// Output: linear radiance, premultiplied by the fabric's coverage alpha.
//
// Objects without a fabric have their own program (opaque.frag), not a branch
// here: llvmpipe runs both sides of a branch under a mask, so a floor drawn with
// this program paid for the fabric's shading (the 1080p bench cloth's floor and
// ball alone took 525 ms, 399 ms with their own program; docs/gpu.md).

#include "fabric.glsl"

in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;

uniform vec3 u_ambient;
uniform vec3 u_eye;
// Orthographic cameras look along one direction: towards the viewer, normalised.
uniform bool u_orthographic;
uniform vec3 u_towards_viewer;

layout(location = 0) out vec4 o_radiance;

// Below this a fabric fragment is a hole: less than one 8-bit step of coverage.
const float kMinCoverage = 1.0 / 256.0;

void main() {
  mat3 frame = ClothFrame(v_normal, v_tangent, gl_FrontFacing);
  vec3 view = u_orthographic ? u_towards_viewer : normalize(u_eye - v_position);
  vec4 shaded = ShadeFabric(v_uv, v_position, frame[2], frame[0], frame[1], view, u_ambient);
  // A hole writes no depth, so cloth drawn later behind it still shows.
  if (shaded.a < kMinCoverage) discard;
  // Premultiplied: blended over what lies behind (SvbrdfRenderer draws cloth last).
  o_radiance = vec4(shaded.rgb * shaded.a, shaded.a);
}
