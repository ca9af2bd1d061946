#include "tests/core/methods/method_test_data.h"

#include <algorithm>
#include <cmath>

#include "core/acquire/hemisphere_directions.h"

namespace loom {

RadianceSamples SyntheticSamples(uint32_t resolution, uint32_t views, uint32_t lights, bool holes) {
  RadianceSamples samples(resolution, HemisphereGridDirections(views), HemisphereGridDirections(lights));
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    const glm::vec3 tint(0.3f + 0.05f * static_cast<float>(texel % 7), 0.5f - 0.03f * static_cast<float>(texel % 5),
                         0.2f + 0.04f * static_cast<float>(texel % 3));
    for (size_t view = 0; view < samples.view_count(); ++view) {
      const glm::vec3 v = samples.view_directions[view];
      const bool empty = holes && (texel + view) % 5 == 0;
      samples.alpha[samples.AlphaIndex(texel, view)] = empty ? 0.0f : 0.25f + 0.75f * v.z;
      if (empty) continue;
      for (size_t light = 0; light < samples.light_count(); ++light) {
        const glm::vec3 l = samples.light_directions[light];
        const float shape = l.z * (0.4f + 0.6f * std::pow(std::max(glm::dot(v, glm::vec3(-l.x, -l.y, l.z)), 0.0f), 3.0f));
        samples.radiance[samples.RadianceIndex(texel, view, light)] = tint * shape;
      }
    }
  }
  return samples;
}

RadianceSamples WithViewHeights(RadianceSamples samples, float base) {
  for (size_t view = 0; view < samples.view_count(); ++view) {
    const glm::vec3 v = samples.view_directions[view];
    samples.view_heights[view] = base * (1.0f + 0.4f * (1.0f - v.z) + 0.1f * v.x);
  }
  return samples;
}

}  // namespace loom
