#include "core/fabric/woven_tile.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/fabric/cardinal_spline.h"
#include "core/fabric/weave_pattern.h"

namespace loom {
namespace {

uint32_t ThreadYarn(const google::protobuf::RepeatedField<uint32_t>& colours, uint32_t thread) {
  return colours.empty() ? 0 : colours.Get(static_cast<int>(thread % colours.size()));
}

}  // namespace

TileYarns BuildWovenYarns(const v1::FabricSpec& fabric, int samples_per_crossing) {
  const v1::WovenSpec& woven = fabric.woven();
  const WeaveMatrix weave(woven);
  const uint32_t n = weave.size();
  const float inclination = woven.inclination_degrees() * std::numbers::pi_v<float> / 180.0f;
  const float crimp = std::tan(inclination) / 3.0f;
  // Thicker than this, crossing threads touch (see woven_tile.h).
  const float max_thickness = crimp * std::cos(inclination) / kWovenCrimpClearance;
  const float half_width = 0.5f * (1.0f - woven.gap_ratio());

  TileYarns tile;
  tile.model_to_tile = glm::vec3(1.0f / static_cast<float>(n));
  // Thread t of a direction: warps (along y) then wefts (along x).
  for (const bool warp : {true, false}) {
    for (uint32_t thread = 0; thread < n; ++thread) {
      const uint32_t yarn_index = ThreadYarn(warp ? woven.warp_colours() : woven.weft_colours(), thread);
      const float half_thickness =
          std::min({fabric.yarns(yarn_index).radius(), half_width, max_thickness});
      // The thread's height at each crossing, and its straight course in the plane.
      std::vector<float> heights;
      for (uint32_t cross = 0; cross < n; ++cross) {
        const bool up = warp ? weave.WarpOver(thread, cross) : !weave.WarpOver(cross, thread);
        heights.push_back(up ? crimp : -crimp);
      }
      const glm::vec3 along = warp ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
      const glm::vec3 start = (static_cast<float>(thread) + 0.5f) * glm::vec3(along.y, along.x, 0) + 0.5f * along;
      constexpr float kFlatOnCrossings = 1.0f;  // tension
      const std::vector<SplineSample<float>> profile =
          SamplePeriodicCardinalSpline<float>(heights, 0.0f, kFlatOnCrossings, samples_per_crossing);
      PeriodicYarn yarn;
      yarn.period = static_cast<float>(n) * along;
      yarn.shape = SectionShape::kLens;
      for (size_t i = 0; i < profile.size(); ++i) {
        const float t = static_cast<float>(i) / static_cast<float>(samples_per_crossing);
        yarn.points.push_back(start + t * along + glm::vec3(0, 0, profile[i].position));
        yarn.tangents.push_back(glm::normalize(along + glm::vec3(0, 0, profile[i].derivative)));
      }
      // Exactly one period: the closing point is the first moved by the period.
      yarn.points.back() = yarn.points.front() + yarn.period;
      yarn.section.assign(yarn.points.size(), glm::vec2(half_width, half_thickness));
      yarn.segment_yarn.assign(yarn.points.size() - 1, yarn_index);
      tile.yarns.push_back(std::move(yarn));
    }
  }
  return tile;
}

}  // namespace loom
