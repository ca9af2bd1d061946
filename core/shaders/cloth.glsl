// Cloth, whatever its method: the fabric's radiance and coverage at a fragment from
// the method's ShadeFabricTexel (defined by the method's shader, included before
// this file), blended over texels, levels and the anisotropic footprint, under the
// scene's lights with macro-scale shadows and ambient light, alpha for holes.
// Output: linear radiance, premultiplied by the fabric's coverage alpha.
//
// Objects without a fabric have their own program (opaque.frag), not a branch
// here: llvmpipe runs both sides of a branch under a mask, so a floor drawn with
// this program paid for the fabric's shading (the 1080p bench cloth's floor and
// ball alone took 525 ms, 399 ms with their own program; docs/gpu.md).

// One level at `tile`: the shadings of its taps (fabric_surface.glsl FabricTap: the
// texel it falls in, the paper's lookup, or with LOOM_BILINEAR_TEXELS the four around
// it), blended. Blending shadings, not parameters: a mean of
// lobes is not the lobe of a mean (blending the parameters measured −0.31 dB on the
// bench set, blending the shadings +1.6 dB). The 1×1 level takes the same path (its
// four taps are the one texel, weights summing to 1): a branch for it cost llvmpipe,
// which runs both sides of a branch, a fifth shading on every level (1080p bench
// cloth 712 → 631 ms without it).
vec4 ShadeFabricLevel(vec2 tile, int level, FabricFragment fragment) {
  vec4 result = vec4(0.0);
  for (int i = 0; i < kFabricTaps; ++i) {
    ivec2 texel;
    float weight = FabricTap(tile, level, i, texel);
    result += weight * ShadeFabricTexel(texel, level, fragment);
  }
  return result;
}

// The footprint's one or two levels at `tile`, blended.
vec4 ShadeFabricLevels(vec2 tile, FabricFootprint f, FabricFragment fragment) {
  vec4 result = ShadeFabricLevel(tile, f.level0, fragment);
  if (f.blend > 0.0) result = mix(result, ShadeFabricLevel(tile, f.level1, fragment), f.blend);
  return result;
}

// The fabric's radiance and alpha at a fragment. `uv` is the mesh uv (at the sample
// when shaded per sample), `pixel_uv` the uv at the pixel's centre; the frame
// (normal, tangent, bitangent) is the mesh's, facing the viewer; `towards_viewer`
// is the unit world direction to the eye.
vec4 ShadeFabric(vec2 uv, vec2 pixel_uv, vec3 position, vec3 normal, vec3 tangent, vec3 bitangent,
                 vec3 towards_viewer, vec3 ambient) {
  mat3 to_surface = transpose(mat3(tangent, bitangent, normal));
  vec3 view = to_surface * towards_viewer;
  FabricFragment fragment = GatherFabricFragment(view, to_surface, position, normal, ambient);
  vec2 tile = FabricTileOnGrid(uv, view, fragment.view_grid);
  // The footprint before the shading loop: derivatives are undefined inside it.
  FabricFootprint f = FabricLevels(tile);
  tile += (pixel_uv - uv) * u_fabric_repeat * f.centring;  // the view's offset is the same at both
#ifdef LOOM_ANISOTROPIC_LEVELS
  vec4 result = vec4(0.0);
  for (int i = 0; i < f.samples; ++i) {
    vec2 at = tile + f.axis * ((float(i) + 0.5) / float(f.samples) - 0.5);
    result += ShadeFabricLevels(at, f, fragment);
  }
  result /= float(f.samples);
#else
  vec4 result = ShadeFabricLevels(tile, f, fragment);
#endif
#ifdef LOOM_FABRIC_DECODER
  // A method that decodes its radiance once per fragment (neural.glsl) from values
  // the texture filter blends; its texels' blend is a per-view gain it scales.
  result.rgb = DecodeFabric(tile, f, fragment, result.rgb);
#endif
  return result;
}

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
  vec4 shaded = ShadeFabric(v_uv, interpolateAtOffset(v_uv, vec2(0.0)), v_position, frame[2], frame[0], frame[1], view, u_ambient);
  // A hole writes no depth, so cloth drawn later behind it still shows.
  if (shaded.a < kMinCoverage) discard;
  // Premultiplied: blended over what lies behind (GpuRenderer draws cloth last).
  o_radiance = vec4(shaded.rgb * shaded.a, shaded.a);
}
