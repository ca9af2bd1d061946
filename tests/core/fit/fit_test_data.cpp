#include "tests/core/fit/fit_test_data.h"

#include <cmath>
#include <random>

#include "core/acquire/hemisphere_directions.h"

namespace loom::testing {
namespace {

glm::vec3 LutAt(const std::vector<glm::vec3>& lut, uint32_t view) { return lut.empty() ? glm::vec3(1.0f) : lut[view]; }

// Calls body(view index, light, view) for every visible pair.
template <typename Body>
void ForEachPair(const SyntheticTexel& texel, uint32_t view_count, uint32_t light_count, Body body) {
  const std::vector<glm::vec3> views = HemisphereGridDirections(view_count);
  const std::vector<glm::vec3> lights = HemisphereGridDirections(light_count);
  for (uint32_t v = 0; v < view_count; ++v) {
    if (texel.visible && !texel.visible(v, views[v])) continue;
    for (const glm::vec3& l : lights) body(v, l, views[v]);
  }
}

}  // namespace

glm::vec3 RenderModel(const LafortuneBrdf& brdf, const std::vector<glm::vec3>& lut, uint32_t view_index,
                      glm::vec3 light, glm::vec3 view) {
  return LutAt(lut, view_index) * brdf.Evaluate(light, view);
}

TexelSamples MakeTexelSamples(const SyntheticTexel& texel, uint32_t view_count, uint32_t light_count) {
  std::mt19937 random(texel.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  TexelSamples samples(view_count);
  ForEachPair(texel, view_count, light_count, [&](uint32_t v, glm::vec3 l, glm::vec3 d) {
    glm::vec3 r = RenderModel(texel.brdf, texel.lut, v, l, d);
    if (texel.noise > 0.0) {
      for (int c = 0; c < 3; ++c) r[c] *= static_cast<float>(1.0 + texel.noise * gauss(random));
    }
    samples.Add(l, d, v, r);
  });
  return samples;
}

RenderError CompareRenders(const SyntheticTexel& truth, const TexelFit& fit, uint32_t view_count,
                           uint32_t light_count) {
  double squared = 0.0, sum = 0.0;
  size_t count = 0;
  ForEachPair(truth, view_count, light_count, [&](uint32_t v, glm::vec3 l, glm::vec3 d) {
    const glm::dvec3 expected = RenderModel(truth.brdf, truth.lut, v, l, d);
    const glm::dvec3 e = glm::dvec3(RenderModel(fit.brdf, fit.lut, v, l, d)) - expected;
    squared += glm::dot(e, e);
    sum += expected.x + expected.y + expected.z;
    count += 3;
  });
  return {std::sqrt(squared / count), sum / count};
}

}  // namespace loom::testing
