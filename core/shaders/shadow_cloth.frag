#version 450 core
// Cloth in a shadow map (core/render/shadow_maps.cpp): depth where its yarns stop
// the light, none where it passes through the holes. A map texel holds one depth,
// so coverage alpha (fabric_surface.glsl FabricCoverage, for the direction towards the
// light) becomes the fraction of texels written, an ordered 4×4 dither: the
// lights' 3×3 PCF with bilinear depth compares reads about 4×4 texels, so a
// receiver behind cloth of coverage a gets about 1 − a of the light — as the
// reference's shadow rays, which pass through the real holes (reference_renderer.cpp).

#include "fabric_surface.glsl"

in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;

uniform vec4 u_light;  // world: w 0, xyz the unit direction towards the light; w 1, xyz its position
uniform int u_dither_seed;     // the caster's index: two cloth objects never share a pattern

// Bayer's 4×4 thresholds, (i + ½)/16 in this order.
const float kBayer[16] = float[](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0, 3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);

void main() {
  mat3 frame = ClothFrame(v_normal, v_tangent, gl_FrontFacing);  // facing the light
  vec3 towards_light = u_light.w == 0.0 ? u_light.xyz : normalize(u_light.xyz - v_position);
  vec3 light = transpose(frame) * towards_light;
  vec2 tile = FabricTile(v_uv, light);
  float coverage = FabricCoverage(tile, FabricLevels(tile), light);
  // The pattern is shifted per tile and per object, so two layers of cloth over one
  // map texel seldom share a threshold: light through both is (1 − a₁)(1 − a₂), not
  // 1 − max(a₁, a₂). (A fold is one object: its layers differ in tile.)
  uvec2 index = uvec2(ivec2(floor(tile)));
  uint h = index.x * 0x9E3779B9u ^ index.y * 0x85EBCA6Bu ^ uint(u_dither_seed) * 0xC2B2AE35u;
  h ^= h >> 15;
  h *= 0x27D4EB2Fu;
  h ^= h >> 13;
  ivec2 p = (ivec2(gl_FragCoord.xy) + ivec2(h & 3u, (h >> 2) & 3u)) & 3;
  if (coverage <= (kBayer[p.y * 4 + p.x] + 0.5) / 16.0) discard;
}
