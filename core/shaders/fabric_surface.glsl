// What every fabric method's cloth shading shares (core/methods/fabric_method.h):
// the cloth's frame, the tile coordinate where a ray meets the sampled face, the
// level from the screen footprint, the fragment's view and lights gathered once, and
// the view atlas every method's asset has: per level (mip ℓ = level ℓ), a
// (res_ℓ·k)² texture of one k×k block of views per texel, the method's rgb and the
// coverage alpha, interpolated bilinearly between stored views. The surface frame
// is the tile's frame: tile x along u, y along v, z along the normal.
//
// A method's shader defines LOOM_FABRIC_LIGHT_GRID before including this file when
// it stores lights on a grid too. Derivations: docs/methods.md.

#include "hemisphere_map.glsl"
#include "lights.glsl"

uniform sampler2D u_fabric_views;        // mip ℓ: (res_ℓ·k)² atlas of k×k view blocks
uniform int u_fabric_levels;
uniform int u_fabric_resolution;         // level-0 texels per tile side
uniform int u_fabric_view_side;          // k: the view grid is k×k
uniform vec2 u_fabric_repeat;            // tiles across the uv square (t_N)
uniform sampler2D u_fabric_view_heights; // k×k: each stored view's sampling height, tile z
uniform int u_level_mode;                // 1 none, 2 nearest, 3 trilinear, 4 anisotropic (LevelMode)
uniform float u_lod_bias;                // levels added to the footprint's (render.lod_bias); 0 in the shadow pass
uniform float u_sample_lod_bias;         // shaded per MSAA sample: −½·log2(samples), else 0 (FabricLevels)
uniform bool u_back_sheet;               // a back sheet shades the lights behind the surface,
                                         // their directions mirrored through it (FabricAsset::back)
#ifdef LOOM_FABRIC_LIGHT_GRID
uniform int u_fabric_light_side;         // the light grid is k_l×k_l
#endif

// A method's values in RGB. A sheet of colour components (LOOM_COLOUR_SHEET,
// core/methods/colour_sheets.h) holds components, and u_colour_mix (GpuRenderer
// SheetDraw::colours: the albedos of the yarns they belong to) takes them to RGB. A
// method applies it to each light's and the ambient's share before their colour
// multiplies it: a coloured light times the sum of components is not the sum of the
// components' colours times the light.
#ifdef LOOM_COLOUR_SHEET
uniform mat3 u_colour_mix;
vec3 SheetRgb(vec3 channels) { return u_colour_mix * channels; }
#else
vec3 SheetRgb(vec3 channels) { return channels; }
#endif

// The mesh's frame at a fragment as columns (tangent along +u, bitangent, normal),
// turned towards the side it is seen from: cloth is lit and seen from either side,
// and seen from behind, a surface turns its normal and with it the bitangent.
mat3 ClothFrame(vec3 normal, vec4 tangent, bool front_facing) {
  vec3 n = normalize(normal);
  if (!front_facing) n = -n;
  vec3 t = normalize(tangent.xyz - n * dot(n, tangent.xyz));
  vec3 b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0);
  return mat3(t, b, n);
}

// Texels per tile side at `level`.
int FabricResolution(int level) { return max(u_fabric_resolution >> level, 1); }

// What every shading of a fragment shares, gathered once however many texels the
// fragment shades (two levels; four texels a level with bilinear texels; N points
// with anisotropic levels): the view, where it falls in the view atlas's
// grid, and each light's direction and irradiance times its visibility. The shadow
// map's nine taps per light and the view's grid position (an atan) were the
// dearest parts of a shading, and none of it depends on the texel.
struct FabricFragment {
  vec3 view;                          // unit, surface frame
  vec2 view_grid;                     // in a texel's k×k block of the LUT, clamped to it
  float beyond_ring;                  // how far past the outermost stored ring, [0, 1]
  vec3 light_direction[kMaxLights];   // unit, surface frame
  vec3 light_irradiance[kMaxLights];  // times the light's visibility
  vec3 ambient;
#ifdef LOOM_FABRIC_LIGHT_GRID
  // For methods that store lights on a grid (u_fabric_light_side): where each light
  // falls in it, clamped, and its weight: 0 below the horizon, fading from 1 at the
  // outermost stored ring to 0 at the horizon (radiance there holds cos θ_l → 0).
  vec2 light_grid[kMaxLights];
  float light_weight[kMaxLights];
#endif
};

// Where a direction (unit, surface frame) falls in a k×k hemisphere grid, clamped
// to it, and how far past the outermost stored ring it lies, [0, 1]. A view atlas
// value is bilinear between the stored views (acquisition's views, in tile space)
// inside a texel's k×k block; the clamp keeps the filter from reading a neighbour.
void LocateOnGrid(vec3 direction, float k, out vec2 grid, out float beyond_ring) {
  vec2 unclamped = HemisphereGridCoordinates(direction, k);
  grid = clamp(unclamped, vec2(0.0), vec2(k - 1.0));
  vec2 beyond = max(-unclamped, unclamped - (k - 1.0));
  beyond_ring = clamp(2.0 * max(beyond.x, beyond.y), 0.0, 1.0);
}

// Where a view falls in the view atlas's k×k grid. Coverage between the outermost stored ring of views (grid 0 or k − 1) and the
// horizon (−½ or k − ½): a yarn layer of any thickness hides its holes as the view
// nears the horizon (a gap g between yarns of height h closes at tan θ = g/h), so
// alpha is 1 there; it is interpolated towards 1 instead of held at the last
// ring's value, which let a loose weave at 85° show holes the reference does not
// (docs/stability.md).
void LocateFabricView(vec3 direction, out vec2 grid, out float beyond_ring) {
  LocateOnGrid(direction, float(u_fabric_view_side), grid, beyond_ring);
}

FabricFragment GatherFabricFragment(vec3 view, mat3 to_surface, vec3 position, vec3 normal, vec3 ambient) {
  FabricFragment fragment;
  fragment.view = view;
  LocateFabricView(view, fragment.view_grid, fragment.beyond_ring);
  fragment.ambient = ambient;
  for (int i = 0; i < u_light_count; ++i) {
    vec3 irradiance;
    vec3 direction = to_surface * LightDirection(i, position, irradiance);
    float side = u_back_sheet ? -1.0 : 1.0;
    direction.z *= side;
    fragment.light_direction[i] = direction;
    fragment.light_irradiance[i] = irradiance * LightVisibility(i, position, normal * side);
#ifdef LOOM_FABRIC_LIGHT_GRID
    float beyond_ring;
    LocateOnGrid(fragment.light_direction[i], float(u_fabric_light_side), fragment.light_grid[i], beyond_ring);
    fragment.light_weight[i] = fragment.light_direction[i].z > 0.0 ? 1.0 - beyond_ring : 0.0;
#endif
  }
  return fragment;
}

// The view atlas's value (the method's rgb, coverage alpha) of texel `texel` of
// `level` for a view at `view_grid`.
vec4 FetchFabricView(ivec2 texel, int level, vec2 view_grid, float beyond_ring) {
  float k = float(u_fabric_view_side);
  vec2 atlas = (vec2(texel) * k + view_grid + 0.5) / (float(FabricResolution(level)) * k);
  vec4 value = textureLod(u_fabric_views, atlas, float(level));
  value.a = mix(value.a, 1.0, beyond_ring);
  return value;
}

// The texel of `level` that `tile` falls in (the paper's lookup).
ivec2 FabricTexelAt(vec2 tile, int level) {
  int resolution = FabricResolution(level);
  return min(ivec2(fract(tile) * float(resolution)), ivec2(resolution - 1));
}

// The texels a level's shading at `tile` blends: with LOOM_BILINEAR_TEXELS the four
// around it, bilinearly, across the tile's periodic edges; else the one it falls in.
#ifdef LOOM_BILINEAR_TEXELS
const int kFabricTaps = 4;
#else
const int kFabricTaps = 1;
#endif

// Tap i < kFabricTaps of `level` at `tile`: its texel and its weight (the weights sum
// to 1).
float FabricTap(vec2 tile, int level, int i, out ivec2 texel) {
#ifdef LOOM_BILINEAR_TEXELS
  int resolution = FabricResolution(level);
  vec2 at = fract(tile) * float(resolution) - 0.5;
  vec2 corner = floor(at), weight = at - corner;
  ivec2 offset = ivec2(i & 1, i >> 1);
  texel = (ivec2(corner) + offset + resolution) % resolution;
  vec2 w = mix(1.0 - weight, weight, vec2(offset));
  return w.x * w.y;
#else
  texel = FabricTexelAt(tile, level);
  return 1.0;
#endif
}

// The continuous level λ from the screen footprint of the tile coordinate, in
// level-0 texels; the mode picks level 0, the nearest level or the two nearest.
// The footprint's side is the geometric mean of its two axes (the square of the
// same area), not the longer axis: on cloth seen obliquely the longer axis blurs
// the shorter one away, for a little more flicker (measured: docs/accuracy.md).
//
// Anisotropic mode (compiled apart, with LOOM_ANISOTROPIC_LEVELS defined: its loop
// costs the other modes half as much again on llvmpipe even when it runs once), as
// GPUs filter textures anisotropically: N = the longer axis over the shorter (at
// most kMaxAnisotropy) shadings spread along the longer axis, each at the level of
// the longer axis over N, so that every shading's texel spans about a pixel both
// ways. The area rule point-fetches texels finer than a pixel along the
// foreshortened axis, which alias; the longer axis alone blurs the other. For a
// round footprint both modes agree.
const int kMaxAnisotropy = 8;

// Shaded per MSAA sample (render.shading_rate SAMPLE), each sample reads the level
// of its share of the footprint, ½·log2(samples) finer than the pixel's, where a
// tile (the weave's period) spans more than 2^kSampleSharpenFrom pixels; from there
// to 2^kSampleSharpenTo the bias fades and the sample moves to the pixel's centre,
// and below it every sample shades as the pixel would. On a tile of a few pixels
// the finer level's periodic pattern, point-sampled by four samples, aliases
// (docs/accuracy.md, "Shading rate"). With 32 texels a tile: levels 2.5 to 3.5.
const float kSampleSharpenFrom = 2.5;  // log2 of a tile's span in pixels
const float kSampleSharpenTo = 1.5;

struct FabricFootprint {
  int level0;
  int level1;
  float blend;
  int samples;     // shadings along `axis`
  vec2 axis;       // the longer axis of the pixel's footprint, tile units
  float centring;  // shaded per sample: 0 at the sample, 1 at the pixel's centre
};

// From the tile coordinate's screen derivatives along x and y.
FabricFootprint FabricLevelsFrom(vec2 du, vec2 dv) {
  float lu = length(du) * float(u_fabric_resolution), lv = length(dv) * float(u_fabric_resolution);
  FabricFootprint f;
  f.samples = 1;  // one shading at the fragment: `axis` is not read
#ifdef LOOM_ANISOTROPIC_LEVELS
  f.axis = lu >= lv ? du : dv;
  float longer = max(lu, lv), shorter = max(min(lu, lv), 1e-8);
  f.samples = clamp(int(ceil(longer / shorter - 0.01)), 1, kMaxAnisotropy);
  float lambda = log2(max(longer / float(f.samples), 1e-8));
#else
  float lambda = 0.5 * log2(max(lu * lv, 1e-16));
#endif
  float tile_span = log2(float(u_fabric_resolution)) - lambda;  // log2 of a tile's pixels
  float sharpen = clamp((tile_span - kSampleSharpenTo) / (kSampleSharpenFrom - kSampleSharpenTo), 0.0, 1.0);
  f.centring = u_sample_lod_bias < 0.0 ? 1.0 - sharpen : 0.0;
  lambda = clamp(lambda + u_lod_bias + u_sample_lod_bias * sharpen, 0.0, float(u_fabric_levels - 1));
  if (u_level_mode == 1) lambda = 0.0;
  if (u_level_mode == 2) lambda = floor(lambda + 0.5);
  f.level0 = int(floor(lambda));
  f.level1 = min(f.level0 + 1, u_fabric_levels - 1);
  f.blend = lambda - float(f.level0);
  return f;
}

#ifndef LOOM_CLOTH_COMPUTE
// At a fragment, in uniform control flow.
FabricFootprint FabricLevels(vec2 tile) { return FabricLevelsFrom(dFdx(tile), dFdy(tile)); }
#endif

// The tile coordinate where a ray from `direction` (unit, surface frame) meets the
// fabric at mesh uv `uv`. Acquisition sampled each view's texels on a plane above
// the macro surface (tile z = 0) by that view's sampling height
// (RadianceSamples::view_heights): look the texel up where the ray crosses the
// plane, its height interpolated between the stored views as the view atlas is.
// Tile units are isotropic (x, y and z scale alike), so the offset is the
// direction's slope times the height; the slope is capped near grazing, where the
// plane is seen edge-on. `grid` is the direction's place in the view grid
// (LocateFabricView). The C++ twin: FabricTileAt (core/methods/direction_grid.h).
vec2 FabricTileOnGrid(vec2 uv, vec3 direction, vec2 grid) {
  ivec2 lower = ivec2(floor(grid));
  ivec2 upper = min(lower + 1, ivec2(u_fabric_view_side - 1));
  vec2 w = grid - vec2(lower);
  float bottom = mix(texelFetch(u_fabric_view_heights, lower, 0).r,
                     texelFetch(u_fabric_view_heights, ivec2(upper.x, lower.y), 0).r, w.x);
  float top = mix(texelFetch(u_fabric_view_heights, ivec2(lower.x, upper.y), 0).r,
                  texelFetch(u_fabric_view_heights, upper, 0).r, w.x);
  return uv * u_fabric_repeat + direction.xy / max(direction.z, 0.1) * mix(bottom, top, w.y);
}

vec2 FabricTile(vec2 uv, vec3 direction) {
  vec2 grid;
  float beyond_ring;
  LocateFabricView(direction, grid, beyond_ring);
  return FabricTileOnGrid(uv, direction, grid);
}

// The fraction of the light arriving from `towards_light` (unit, surface frame)
// that the cloth at `tile` stops: its coverage alpha for that direction (the view
// atlas's alpha, whatever the method) — acquisition's
// fraction of a texel's rays from there that hit yarn — at the footprint's levels,
// blended. The shadow pass (shadow_cloth.frag) lets the rest through the holes.
float FabricCoverage(vec2 tile, FabricFootprint f, vec3 towards_light) {
  vec2 grid;
  float beyond_ring;
  LocateFabricView(towards_light, grid, beyond_ring);
  float coarse = FetchFabricView(FabricTexelAt(tile, f.level1), f.level1, grid, beyond_ring).a;
  float fine = FetchFabricView(FabricTexelAt(tile, f.level0), f.level0, grid, beyond_ring).a;
  return mix(fine, coarse, f.blend);
}
