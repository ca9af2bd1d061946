// The neural method (core/methods/neural/neural_fabric.h): per texel and level a
// latent vector z, decoded with the view and each light by a shared two-layer ReLU
// network f(z, e(v, l)) (e: the directions' encoding, neural_fabric.h
// DirectionEncoding); radiance per unit irradiance A(v)/π ⊙ max(0, f), A the view
// atlas's per-view gain (the texel's ambient response). The texels give A and
// coverage, blended over texels and levels as any method's; the latents are sampled
// by the texture filter (bilinear across the tile's periodic edges with bilinear
// texels, else the texel's own), blended between the footprint's two levels, and
// decoded once per fragment (LOOM_FABRIC_DECODER: cloth.glsl hands the blended A to
// DecodeFabric). With a factored base (LOOM_NEURAL_BASE) the radiance is
// A/π ⊙ max(0, s + f), s the base's shape (factored_terms.glsl) of the same texels and
// levels, blended with the latents' weights. Directions in the tile frame.

#define LOOM_FABRIC_LIGHT_GRID
#define LOOM_FABRIC_DECODER
#include "fabric_surface.glsl"

// The asset's sizes, compiled in (NeuralTextures::ShaderDefines); the file compiled
// on its own (as a test does) takes the largest (core/spec/limits.h).
#ifndef LOOM_NEURAL_CHANNELS
#define LOOM_NEURAL_CHANNELS 16
#define LOOM_NEURAL_HIDDEN 64
#define LOOM_NEURAL_FREQUENCIES 4
#endif
const int kLatents = LOOM_NEURAL_CHANNELS / 4;           // vec4s of a latent
const int kHidden = LOOM_NEURAL_HIDDEN / 4;              // vec4s of a hidden layer
const int kGroups = 1 + 2 * LOOM_NEURAL_FREQUENCIES;     // vec4s of the encoding: (v.xy, l.xy) each
const int kRow1 = kLatents + kGroups;                    // vec4s of a first-layer row: z, then e
// NeuralDecoder::parameters in vec4s: W1 row-major, b1, W2 row-major, b2, W3, b3.
const int kB1 = LOOM_NEURAL_HIDDEN * kRow1;
const int kW2 = kB1 + kHidden;
const int kB2 = kW2 + LOOM_NEURAL_HIDDEN * kHidden;
const int kW3 = kB2 + kHidden;
const int kB3 = kW3 + 3 * kHidden;

layout(std140) uniform NeuralDecoder {
  vec4 u_decoder[kB3 + 1];
};
uniform sampler2DArray u_fabric_latents;  // layer i: z[4i..4i+3]; mip ℓ: level ℓ's res_ℓ² texels; repeat

#ifdef LOOM_NEURAL_BASE
#include "factored_terms.glsl"

// The base's shape for each light at `tile`: its taps' shapes at the footprint's
// levels, blended with the weights the texture filter gives the latents.
void BaseShapes(vec2 tile, FabricFootprint f, FabricFragment fragment, out float shape[kMaxLights]) {
  for (int l = 0; l < u_light_count; ++l) shape[l] = 0.0;
  for (int n = 0; n < 2; ++n) {
    float level_weight = n == 0 ? 1.0 - f.blend : f.blend;
    if (level_weight <= 0.0) continue;
    int level = n == 0 ? f.level0 : f.level1;
    for (int i = 0; i < kFabricTaps; ++i) {
      ivec2 texel;
      float weight = level_weight * FabricTap(tile, level, i, texel);
      vec4 a[kTermLayers];
      FetchViewTerms(texel, level, fragment.view_grid, a);
      for (int l = 0; l < u_light_count; ++l) {
        shape[l] += weight * FactoredShape(a, texel, level, fragment.light_grid[l]);
      }
    }
  }
}
#endif

// The view atlas's part of a texel: the gain A and coverage.
vec4 ShadeFabricTexel(ivec2 texel, int level, FabricFragment fragment) {
  return FetchFabricView(texel, level, fragment.view_grid, fragment.beyond_ring);
}

vec4 FabricLatent(vec2 tile, int level, int layer) {
#ifdef LOOM_BILINEAR_TEXELS
  vec2 at = tile;
#else
  vec2 at = (vec2(FabricTexelAt(tile, level)) + 0.5) / float(FabricResolution(level));
#endif
  return textureLod(u_fabric_latents, vec3(at, float(layer)), float(level));
}

// Group g of a direction's encoding: the direction, then for k < F its sines and
// cosines of 2^k·π times it.
vec2 EncodeDirection(vec2 d, int g) {
  if (g == 0) return d;
  vec2 phase = kPi * float(1 << ((g - 1) / 2)) * d;
  return (g % 2 == 1) ? sin(phase) : cos(phase);
}

// A weight row of kHidden vec4s starting at u_decoder[row], times x.
float DecoderRow(int row, vec4 x[kHidden]) {
  float sum = 0.0;
  for (int i = 0; i < kHidden; ++i) sum += dot(u_decoder[row + i], x[i]);
  return sum;
}

// The fragment's radiance from its blended gain A: A times the ambient light, plus
// A/π times f (plus the base's shape) decoded for each light, clamped at 0, times the
// light's irradiance and grid weight. The first layer's latent and view part is the
// same for every light and computed once.
vec3 DecodeFabric(vec2 tile, FabricFootprint f, FabricFragment fragment, vec3 gain) {
#ifdef LOOM_NEURAL_BASE
  float shape[kMaxLights];
  BaseShapes(tile, f, fragment, shape);
#endif
  vec4 z[kLatents];
  for (int i = 0; i < kLatents; ++i) {
    z[i] = FabricLatent(tile, f.level0, i);
    if (f.blend > 0.0) z[i] = mix(z[i], FabricLatent(tile, f.level1, i), f.blend);
  }
  vec2 view[kGroups];
  for (int g = 0; g < kGroups; ++g) view[g] = EncodeDirection(fragment.view.xy, g);
  float base[LOOM_NEURAL_HIDDEN];
  for (int j = 0; j < LOOM_NEURAL_HIDDEN; ++j) {
    int row = j * kRow1;
    float sum = u_decoder[kB1 + j / 4][j % 4];
    for (int i = 0; i < kLatents; ++i) sum += dot(u_decoder[row + i], z[i]);
    for (int g = 0; g < kGroups; ++g) sum += dot(u_decoder[row + kLatents + g].xy, view[g]);
    base[j] = sum;
  }
  vec3 radiance = vec3(0.0);
  for (int l = 0; l < u_light_count; ++l) {
    vec2 light[kGroups];
    for (int g = 0; g < kGroups; ++g) light[g] = EncodeDirection(fragment.light_direction[l].xy, g);
    vec4 h1[kHidden], h2[kHidden];
    for (int q = 0; q < kHidden; ++q) {
      vec4 pre;
      for (int r = 0; r < 4; ++r) {
        int row = (4 * q + r) * kRow1 + kLatents;
        float sum = base[4 * q + r];
        for (int g = 0; g < kGroups; ++g) sum += dot(u_decoder[row + g].zw, light[g]);
        pre[r] = sum;
      }
      h1[q] = max(pre, 0.0);
    }
    for (int q = 0; q < kHidden; ++q) {
      vec4 pre;
      for (int r = 0; r < 4; ++r) pre[r] = DecoderRow(kW2 + (4 * q + r) * kHidden, h1);
      h2[q] = max(pre + u_decoder[kB2 + q], 0.0);
    }
    vec3 y = vec3(DecoderRow(kW3, h2), DecoderRow(kW3 + kHidden, h2), DecoderRow(kW3 + 2 * kHidden, h2));
    y += u_decoder[kB3].xyz;
#ifdef LOOM_NEURAL_BASE
    y += shape[l];
#endif
    radiance += fragment.light_irradiance[l] * fragment.light_weight[l] * SheetRgb(gain * max(y, vec3(0.0)));
  }
  return fragment.ambient * SheetRgb(gain) + radiance / kPi;
}
