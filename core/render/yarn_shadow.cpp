#include "core/render/yarn_shadow.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/util/vector_math.h"

namespace loom {
namespace {

constexpr int kProfilePhases = 16;
constexpr int kChordSteps = 256;

}  // namespace

std::vector<float> YarnShadowProfile(const YarnSection& section, float optical_density) {
  const float extent = section.extent();
  std::vector<float> chord(kYarnShadowProfileSamples);
  for (int k = 0; k < kYarnShadowProfileSamples; ++k) {
    const float d = extent * static_cast<float>(k) / (kYarnShadowProfileSamples - 1);
    double transmittance = 0.0;
    for (int p = 0; p < kProfilePhases; ++p) {
      const float phase = 2.0f * std::numbers::pi_v<float> * static_cast<float>(p) / kProfilePhases;
      double depth = 0.0;
      const float ds = 2.0f * extent / kChordSteps;
      for (int s = 0; s < kChordSteps; ++s) {
        depth += FibreDensity(section, {d, -extent + ds * (static_cast<float>(s) + 0.5f)}, phase) * ds;
      }
      transmittance += std::exp(-optical_density * depth);
    }
    chord[k] = static_cast<float>(transmittance / kProfilePhases);
  }
  std::vector<float> profile(kYarnShadowProfileSamples, 1.0f);
  const float centre = 1.0f - chord[0];
  if (centre <= 0.0f) return profile;
  for (int k = 0; k < kYarnShadowProfileSamples; ++k) {
    profile[k] = std::clamp(1.0f - kYarnShadowStrength * (1.0f - chord[k]) / centre, 0.0f, 1.0f);
  }
  return profile;
}

std::vector<float> YarnShadows(const std::vector<ShadowSegment>& segments, const YarnShadowProfiles& profiles,
                               glm::vec3 light) {
  std::vector<float> shadow(segments.size(), 1.0f);
  if (segments.empty()) return shadow;
  // The light's view: positions across it, and heights towards it.
  const glm::vec3 e1 = AnyPerpendicular(light), e2 = glm::cross(light, e1);
  const auto across = [&](glm::vec3 p) { return glm::vec2(glm::dot(p, e1), glm::dot(p, e2)); };
  glm::vec2 low(1e30f), high(-1e30f);
  float reach = 0.0f;
  for (const ShadowSegment& s : segments) {
    low = glm::min(low, glm::min(across(s.start), across(s.end)));
    high = glm::max(high, glm::max(across(s.start), across(s.end)));
    reach = std::max(reach, profiles.extent[s.yarn] * s.radius);
  }
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
    const float r = profiles.extent[s.yarn] * s.radius;
    const glm::ivec2 c0 = cell_of(glm::min(across(s.start), across(s.end)) - r);
    const glm::ivec2 c1 = cell_of(glm::max(across(s.start), across(s.end)) + r);
    for (int y = c0.y; y <= c1.y; ++y) {
      for (int x = c0.x; x <= c1.x; ++x) grid[static_cast<size_t>(y) * size.x + x].push_back(i);
    }
  }
  for (size_t j = 0; j < segments.size(); ++j) {
    const ShadowSegment& shaded = segments[j];
    const glm::vec3 middle = 0.5f * (shaded.start + shaded.end);
    const glm::vec2 point = across(middle);
    const float height = glm::dot(middle, light);
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
      const glm::vec2 a = across(s.start), b = across(s.end);
      const glm::vec2 ab = b - a;
      const float u = glm::dot(ab, ab) > 0.0f ? std::clamp(glm::dot(point - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f)
                                              : 0.0f;
      if (glm::mix(glm::dot(s.start, light), glm::dot(s.end, light), u) <= height) continue;
      const float d = glm::distance(point, a + u * ab) / s.radius;
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
