// Cloth, whatever its method: the fabric's radiance and coverage at a fragment from
// the method's ShadeFabricTexel (defined by the method's shader, included before
// this file), blended over texels, levels and the anisotropic footprint, under the
// scene's lights with macro-scale shadows and ambient light, alpha for holes.
// Output: linear radiance, premultiplied by the fabric's coverage alpha.
//
// Objects without a fabric have their own program (opaque.frag), not a branch
// here: llvmpipe runs both sides of a branch under a mask, so a floor drawn with
// this program would pay for the fabric's shading (docs/gpu.md, "llvmpipe frame
// time").

// One level at `tile`: the shadings of its taps (fabric_surface.glsl FabricTap: the
// texel it falls in, the paper's lookup, or with LOOM_BILINEAR_TEXELS the four around
// it), blended. Blending shadings, not parameters: a mean of lobes is not the lobe of
// a mean (docs/accuracy.md). The 1×1 level takes the same path (its four taps are the
// one texel, weights summing to 1): a branch for it would cost llvmpipe, which runs
// both sides of a branch, a fifth shading on every level.
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

// The fabric's radiance and alpha at a point whose footprint `f` is known: the
// view's shadings over the footprint's levels (and with anisotropic levels, along
// its longer axis), decoded where the method decodes.
vec4 ShadeFabricAt(vec2 tile, FabricFootprint f, FabricFragment fragment) {
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

// The view in the surface frame (tangent, bitangent, normal) and the tile
// coordinate it sees at mesh uv `uv`: what the footprint's derivatives are taken of.
vec2 FabricTileSeen(vec2 uv, mat3 to_surface, vec3 towards_viewer) {
  vec3 view = to_surface * towards_viewer;
  vec2 grid;
  float beyond_ring;
  LocateFabricView(view, grid, beyond_ring);
  return FabricTileOnGrid(uv, view, grid);
}

// The light-dependent part of a shading: the fragment's lights gathered and the
// fabric shaded at `tile` over footprint `f`. `uv` is the mesh uv (at the sample
// when shaded per sample), `pixel_uv` the uv at the pixel's centre; the frame
// (normal, tangent, bitangent) is the mesh's, facing the viewer; `towards_viewer`
// is the unit world direction to the eye.
vec4 ShadeFabricWithFootprint(vec2 tile, FabricFootprint f, vec2 uv, vec2 pixel_uv, vec3 position,
                              mat3 frame, vec3 towards_viewer, vec3 ambient) {
  mat3 to_surface = transpose(frame);
  FabricFragment fragment =
      GatherFabricFragment(to_surface * towards_viewer, to_surface, position, frame[2], ambient);
  tile += (pixel_uv - uv) * u_fabric_repeat * f.centring;  // the view's offset is the same at both
  return ShadeFabricAt(tile, f, fragment);
}

// Below this a fabric fragment is a hole: less than one 8-bit step of coverage.
const float kMinCoverage = 1.0 / 256.0;

// The entry points. Every method's cloth program is this file's: by default the
// fragment shader that shades cloth (the fragment pass); the compute pass
// (GpuRenderer, render.shading_pass) compiles the same method file three more ways:
// LOOM_CLOTH_GBUFFER, a fragment shader writing what a shading needs per pixel of
// the nearest cloth surface, then (u_peel) of the nearest behind it;
// LOOM_CLOTH_COMPUTE, the compute shader that shades those pixels; and
// LOOM_CLOTH_COMPOSITE, the fragment shader that blends the computed shadings into
// the multisampled frame as the cloth is drawn, shading in place the fragments the
// G-buffers do not hold (silhouette pixels whose centre misses the cloth, a third
// layer). A G-buffer layer, one pixel each (ClothGbuffer): 0 position, window depth
// (−1: no cloth); 1 normal, bitangent sign; 2 tangent; 3 uv; 4 the tile coordinate's
// screen derivatives (FabricLevelsFrom).
#ifdef LOOM_CLOTH_COMPUTE

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform readonly image2D u_gbuffer[5];
layout(binding = 5, rgba32f) uniform writeonly image2D u_shaded;

uniform vec3 u_ambient;
uniform vec3 u_eye;
uniform bool u_orthographic;
uniform vec3 u_towards_viewer;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(u_shaded)))) return;
  vec4 g0 = imageLoad(u_gbuffer[0], pixel);
  if (g0.w < 0.0) return;  // no cloth here
  vec4 g1 = imageLoad(u_gbuffer[1], pixel), g2 = imageLoad(u_gbuffer[2], pixel);
  vec2 uv = imageLoad(u_gbuffer[3], pixel).xy;
  vec4 derivatives = imageLoad(u_gbuffer[4], pixel);
  mat3 frame = mat3(g2.xyz, cross(g1.xyz, g2.xyz) * g1.w, g1.xyz);
  vec3 view = u_orthographic ? u_towards_viewer : normalize(u_eye - g0.xyz);
  vec2 tile = FabricTileSeen(uv, transpose(frame), view);
  FabricFootprint f = FabricLevelsFrom(derivatives.xy, derivatives.zw);
  imageStore(u_shaded, pixel, ShadeFabricWithFootprint(tile, f, uv, uv, g0.xyz, frame, view, u_ambient));
}

#else

in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;

uniform vec3 u_ambient;
uniform vec3 u_eye;
// Orthographic cameras look along one direction: towards the viewer, normalised.
uniform bool u_orthographic;
uniform vec3 u_towards_viewer;

#ifdef LOOM_CLOTH_GBUFFER

uniform bool u_peel;  // the second layer: only what lies behind the first
layout(binding = 0, rgba32f) uniform readonly image2D u_nearer;  // the first layer's attachment 0

layout(location = 0) out vec4 o_gbuffer0;
layout(location = 1) out vec4 o_gbuffer1;
layout(location = 2) out vec4 o_gbuffer2;
layout(location = 3) out vec4 o_gbuffer3;
layout(location = 4) out vec4 o_gbuffer4;

void main() {
  mat3 frame = ClothFrame(v_normal, v_tangent, gl_FrontFacing);
  vec3 view = u_orthographic ? u_towards_viewer : normalize(u_eye - v_position);
  vec2 tile = FabricTileSeen(v_uv, transpose(frame), view);
  vec4 derivatives = vec4(dFdx(tile), dFdy(tile));
  if (u_peel) {
    float nearer = imageLoad(u_nearer, ivec2(gl_FragCoord.xy)).w;
    if (nearer >= 0.0 && gl_FragCoord.z <= nearer) discard;
  }
  o_gbuffer0 = vec4(v_position, gl_FragCoord.z);
  o_gbuffer1 = vec4(frame[2], dot(cross(frame[2], frame[0]), frame[1]) < 0.0 ? -1.0 : 1.0);
  o_gbuffer2 = vec4(frame[0], 0.0);
  o_gbuffer3 = vec4(v_uv, 0.0, 0.0);
  o_gbuffer4 = derivatives;
}

#else

layout(location = 0) out vec4 o_radiance;

#ifdef LOOM_CLOTH_COMPOSITE
const int kGbufferLayers = 2;  // ClothGbuffer::kLayers
layout(binding = 0, rgba32f) uniform readonly image2D u_held[kGbufferLayers];    // each layer's attachment 0
layout(binding = 2, rgba32f) uniform readonly image2D u_shaded[kGbufferLayers];  // its shadings
layout(binding = 0, offset = 0) uniform atomic_uint u_shaded_in_place;          // ClothGbuffer::Counter
#endif

void main() {
  mat3 frame = ClothFrame(v_normal, v_tangent, gl_FrontFacing);
  vec3 view = u_orthographic ? u_towards_viewer : normalize(u_eye - v_position);
  // The footprint in uniform control flow: derivatives are undefined inside a branch
  // or the shading loop.
  vec2 tile = FabricTileSeen(v_uv, transpose(frame), view);
  FabricFootprint f = FabricLevels(tile);
#ifdef LOOM_CLOTH_COMPOSITE
  // The computed shading of the layer that holds this fragment's surface, else one
  // shaded here. The layer's pixel centre lies on the same surface when its depth is
  // within the depth's change across the pixel: a neighbouring triangle of the mesh
  // (each triangle a pixel straddles has a fragment in it), or the same one
  // rasterised with a sample count of its own. Another layer lies farther off.
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float tolerance = fwidth(gl_FragCoord.z);
  vec4 shaded;
  float nearest = tolerance;
  bool computed = false;
  for (int k = 0; k < kGbufferLayers; ++k) {
    float held = imageLoad(u_held[k], pixel).w;
    float apart = abs(held - gl_FragCoord.z);
    if (held >= 0.0 && apart <= nearest) {
      shaded = imageLoad(u_shaded[k], pixel);
      nearest = apart;
      computed = true;
    }
  }
  if (!computed) {
    shaded = ShadeFabricWithFootprint(tile, f, v_uv, v_uv, v_position, frame, view, u_ambient);
    atomicCounterIncrement(u_shaded_in_place);
  }
#else
  vec4 shaded = ShadeFabricWithFootprint(tile, f, v_uv, interpolateAtOffset(v_uv, vec2(0.0)), v_position, frame,
                                         view, u_ambient);
#endif
  // A hole writes no depth, so cloth drawn later behind it still shows.
  if (shaded.a < kMinCoverage) discard;
  // Premultiplied: blended over what lies behind (GpuRenderer draws cloth last).
  o_radiance = vec4(shaded.rgb * shaded.a, shaded.a);
}

#endif  // LOOM_CLOTH_GBUFFER
#endif  // LOOM_CLOTH_COMPUTE
