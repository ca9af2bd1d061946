#include "core/render/yarn_shadow.h"

#include <algorithm>
#include <cmath>

#include "core/util/vector_math.h"

namespace loom {
namespace {

// Where points lie as a light sees them: `Across` its view, `Nearer` to it, and the
// world length a unit across spans at a point. A directional light's view is an
// orthographic one along it; a point light's a perspective one from it, about the
// direction to the segments' centre, which points beside or behind the light leave.
class LightView {
 public:
  LightView(const SceneLight& light, const std::vector<ShadowSegment>& segments) : light_(light) {
    glm::vec3 axis = light.vector;
    if (!light.directional) {
      glm::vec3 centre(0.0f);
      for (const ShadowSegment& s : segments) centre += 0.5f * (s.start + s.end);
      centre /= static_cast<float>(segments.size());
      axis = glm::length(centre - light.vector) > 0.0f ? glm::normalize(light.vector - centre) : glm::vec3(0, 0, 1);
    }
    w_ = axis;  // towards the light
    e1_ = AnyPerpendicular(w_);
    e2_ = glm::cross(w_, e1_);
  }
  // Whether the light sees `p` in its view (a point light: in front of it).
  bool Sees(glm::vec3 p) const { return light_.directional || Depth(p) > kMinDepth; }
  glm::vec2 Across(glm::vec3 p) const {
    if (light_.directional) return {glm::dot(p, e1_), glm::dot(p, e2_)};
    const glm::vec3 d = p - light_.vector;
    return glm::vec2(glm::dot(d, e1_), glm::dot(d, e2_)) / Depth(p);
  }
  // Larger the nearer the light, along its view's axis (as a shadow map's depth).
  float Nearness(glm::vec3 p) const { return light_.directional ? glm::dot(p, w_) : -Depth(p); }
  float Scale(glm::vec3 p) const { return light_.directional ? 1.0f : Depth(p); }

 private:
  static constexpr float kMinDepth = 1e-4f;
  float Depth(glm::vec3 p) const { return glm::dot(light_.vector - p, w_); }
  SceneLight light_;
  glm::vec3 w_, e1_, e2_;
};

}  // namespace

std::vector<float> YarnShadows(const std::vector<ShadowSegment>& segments, const YarnShadowProfiles& profiles,
                               const SceneLight& light) {
  std::vector<float> shadow(segments.size(), 1.0f);
  if (segments.empty()) return shadow;
  const LightView view(light, segments);
  const auto seen = [&](const ShadowSegment& s) { return view.Sees(s.start) && view.Sees(s.end); };
  // Each segment's reach in the light's view, at its nearer end to the light.
  const auto reach_of = [&](const ShadowSegment& s) {
    return profiles.extent[s.yarn] * s.radius / std::min(view.Scale(s.start), view.Scale(s.end));
  };
  glm::vec2 low(1e30f), high(-1e30f);
  float reach = 0.0f;
  for (const ShadowSegment& s : segments) {
    if (!seen(s)) continue;
    low = glm::min(low, glm::min(view.Across(s.start), view.Across(s.end)));
    high = glm::max(high, glm::max(view.Across(s.start), view.Across(s.end)));
    reach = std::max(reach, reach_of(s));
  }
  if (reach == 0.0f) return shadow;
  low -= reach;
  high += reach;
  // Cells of at least a reach (a point's shadowing yarns are in its own cell), and
  // about as many as segments.
  const float side = std::ceil(std::sqrt(static_cast<float>(segments.size())));
  const float cell = std::max({reach, (high.x - low.x) / side, (high.y - low.y) / side, 1e-6f});
  const glm::ivec2 size = glm::ivec2((high - low) / cell) + 1;
  const auto cell_of = [&](glm::vec2 p) {
    return glm::clamp(glm::ivec2((p - low) / cell), glm::ivec2(0), size - 1);
  };
  std::vector<std::vector<uint32_t>> grid(static_cast<size_t>(size.x) * size.y);
  for (uint32_t i = 0; i < segments.size(); ++i) {
    const ShadowSegment& s = segments[i];
    if (!seen(s)) continue;
    const float r = reach_of(s);
    const glm::ivec2 c0 = cell_of(glm::min(view.Across(s.start), view.Across(s.end)) - r);
    const glm::ivec2 c1 = cell_of(glm::max(view.Across(s.start), view.Across(s.end)) + r);
    for (int y = c0.y; y <= c1.y; ++y) {
      for (int x = c0.x; x <= c1.x; ++x) grid[static_cast<size_t>(y) * size.x + x].push_back(i);
    }
  }
  for (size_t j = 0; j < segments.size(); ++j) {
    const ShadowSegment& shaded = segments[j];
    const glm::vec3 middle = 0.5f * (shaded.start + shaded.end);
    if (!view.Sees(middle)) continue;
    const glm::vec2 point = view.Across(middle);
    const float nearness = view.Nearness(middle);
    const float arc = shaded.arc + 0.5f * glm::distance(shaded.start, shaded.end);
    const glm::ivec2 c = cell_of(point);
    float transmittance = 1.0f;
    for (const uint32_t i : grid[static_cast<size_t>(c.y) * size.x + c.x]) {
      if (i == j) continue;
      const ShadowSegment& s = segments[i];
      if (s.chain == shaded.chain) {
        const float other = s.arc + 0.5f * glm::distance(s.start, s.end);
        if (std::abs(other - arc) < profiles.own_chain_radii * shaded.radius) continue;
      }
      // The nearest point of its centre line in the light's view, and whether it lies
      // between the shaded point and the light.
      const glm::vec2 a = view.Across(s.start), b = view.Across(s.end);
      const glm::vec2 ab = b - a;
      const float u = glm::dot(ab, ab) > 0.0f ? std::clamp(glm::dot(point - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f)
                                              : 0.0f;
      const glm::vec3 nearest = glm::mix(s.start, s.end, u);
      if (view.Nearness(nearest) <= nearness) continue;
      const float d = glm::distance(point, a + u * ab) * view.Scale(nearest) / s.radius;
      const float extent = profiles.extent[s.yarn];
      if (d >= extent) continue;
      const std::vector<float>& profile = profiles.profile[s.yarn];
      const float x = d / extent * (kYarnShadowProfileSamples - 1);
      const int k = std::min(static_cast<int>(x), kYarnShadowProfileSamples - 2);
      transmittance *= glm::mix(profile[k], profile[k + 1], x - static_cast<float>(k));
    }
    shadow[j] = transmittance;
  }
  return shadow;
}

}  // namespace loom
