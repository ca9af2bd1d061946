#include "core/methods/tabulated/tabulated_fabric.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/direction_grid.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

// Level 0: the samples as they are.
TabulatedLevel FinestLevel(const RadianceSamples& samples) {
  TabulatedLevel level;
  level.resolution = samples.resolution;
  level.radiance = samples.radiance;
  level.alpha = samples.alpha;
  return level;
}

// Level k + 1 from level k: each texel pools its 2×2 children per (view, light),
// weighted by their alpha (which is the level-0 pooling: a child's alpha is its
// level-0 texels' mean, its radiance their alpha-weighted mean).
TabulatedLevel PooledLevel(const TabulatedLevel& fine, size_t views, size_t lights) {
  TabulatedLevel level;
  level.resolution = fine.resolution / 2;
  level.radiance.assign(level.texel_count() * views * lights, glm::vec3(0.0f));
  level.alpha.assign(level.texel_count() * views, 0.0f);
  for (uint32_t y = 0; y < level.resolution; ++y) {
    for (uint32_t x = 0; x < level.resolution; ++x) {
      const size_t texel = size_t{y} * level.resolution + x;
      for (size_t view = 0; view < views; ++view) {
        float alpha_sum = 0.0f;
        glm::vec3* out = &level.radiance[(texel * views + view) * lights];
        for (uint32_t child = 0; child < 4; ++child) {
          const size_t fine_texel = size_t{2 * y + child / 2} * fine.resolution + 2 * x + child % 2;
          const float alpha = fine.alpha[fine_texel * views + view];
          if (alpha <= 0.0f) continue;
          alpha_sum += alpha;
          const glm::vec3* in = &fine.radiance[(fine_texel * views + view) * lights];
          for (size_t light = 0; light < lights; ++light) out[light] += alpha * in[light];
        }
        level.alpha[texel * views + view] = 0.25f * alpha_sum;
        if (alpha_sum > 0.0f) {
          for (size_t light = 0; light < lights; ++light) out[light] /= alpha_sum;
        }
      }
    }
  }
  return level;
}

// Where a (texel, view) is empty, its radiance is the parent texel's for that view.
void FillHolesFromParent(TabulatedLevel& level, const TabulatedLevel& parent, size_t views, size_t lights) {
  for (uint32_t y = 0; y < level.resolution; ++y) {
    for (uint32_t x = 0; x < level.resolution; ++x) {
      const size_t texel = size_t{y} * level.resolution + x;
      const size_t parent_texel = size_t{y / 2} * parent.resolution + x / 2;
      for (size_t view = 0; view < views; ++view) {
        if (level.alpha[texel * views + view] > 0.0f) continue;
        std::copy_n(&parent.radiance[(parent_texel * views + view) * lights], lights,
                    &level.radiance[(texel * views + view) * lights]);
      }
    }
  }
}

void ComputeAmbient(TabulatedLevel& level, size_t views, size_t lights) {
  const float solid_angle = 2.0f * std::numbers::pi_v<float> / static_cast<float>(lights);
  level.ambient.assign(level.texel_count() * views, glm::vec3(0.0f));
  for (size_t entry = 0; entry < level.ambient.size(); ++entry) {
    glm::vec3 sum(0.0f);
    for (size_t light = 0; light < lights; ++light) sum += level.radiance[entry * lights + light];
    level.ambient[entry] = solid_angle * sum;
  }
}

}  // namespace

double RelativeRmse(const std::vector<double>& squared_residuals, const std::vector<double>& values, size_t count) {
  double residual_sum = 0.0, value_sum = 0.0;
  for (size_t texel = 0; texel < squared_residuals.size(); ++texel) {
    residual_sum += squared_residuals[texel];
    value_sum += values[texel];
  }
  const auto n = static_cast<double>(count);
  return value_sum > 0.0 ? std::sqrt(residual_sum / n) / (value_sum / n) : 0.0;
}

TabulatedFabric TabulateFabric(const RadianceSamples& samples, bool mip_levels) {
  const Stopwatch stopwatch;
  if (mip_levels && !std::has_single_bit(samples.resolution)) {
    throw Error(ErrorCode::kInvalidArgument, "tabulated levels: resolution " + std::to_string(samples.resolution) +
                                                 " is not a power of two");
  }
  TabulatedFabric fabric;
  fabric.view_directions = samples.view_directions;
  fabric.light_directions = samples.light_directions;
  fabric.view_heights = samples.view_heights;
  const size_t views = samples.view_count(), lights = samples.light_count();
  fabric.levels.push_back(FinestLevel(samples));
  while (mip_levels && fabric.levels.back().resolution > 1) {
    fabric.levels.push_back(PooledLevel(fabric.levels.back(), views, lights));
  }
  for (size_t level = fabric.levels.size() - 1; level-- > 0;) {
    FillHolesFromParent(fabric.levels[level], fabric.levels[level + 1], views, lights);
  }
  for (TabulatedLevel& level : fabric.levels) ComputeAmbient(level, views, lights);
  fabric.seconds = stopwatch.Seconds();
  return fabric;
}

glm::vec4 EvaluateTabulated(const TabulatedFabric& fabric, uint32_t level_index, size_t texel, glm::vec3 view,
                            glm::vec3 light) {
  const TabulatedLevel& level = fabric.levels.at(level_index);
  const size_t views = fabric.view_count(), lights = fabric.light_count();
  const uint32_t view_side = GridSide(views);
  const uint32_t light_side = GridSide(lights);
  const GridPoint v = LocateOnGrid(view, view_side);
  const GridPoint l = LocateOnGrid(light, light_side);
  const glm::vec3 radiance = Bilinear<glm::vec3>(v, view_side, [&](size_t stored_view) {
    return Bilinear<glm::vec3>(l, light_side, [&](size_t stored_light) {
      return level.radiance[(texel * views + stored_view) * lights + stored_light];
    });
  });
  const float alpha = Bilinear<float>(v, view_side, [&](size_t stored_view) { return level.alpha[texel * views + stored_view]; });
  return {LightWeight(light, l) * radiance, glm::mix(alpha, 1.0f, v.beyond_ring)};
}

}  // namespace loom
