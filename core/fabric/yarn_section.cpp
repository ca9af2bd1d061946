#include "core/fabric/yarn_section.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace loom {
namespace {

constexpr int kCellPoints = 4;  // per side of a grid cell

}  // namespace

float PlyFibreDensity(float r) {
  if (!(r <= 1.0f)) return 0.0f;
  const float e = std::numbers::e_v<float>;
  const float shape = std::max(0.0f, (e - std::exp(std::max(r, 0.0f))) / (e - 1.0f));
  return (1.0f - 2.0f * kFibreDensityEpsilon) * std::pow(shape, kFibreDensityBeta) + kFibreDensityEpsilon;
}

YarnSection MakeYarnSection(const v1::YarnSpec& yarn) {
  YarnSection section;
  section.plies = std::max<uint32_t>(yarn.plies(), 1);
  section.fuzz = std::clamp(yarn.fuzz(), 0.0f, 1.0f);
  if (section.plies >= 2) {
    const float s = std::sin(std::numbers::pi_v<float> / static_cast<float>(section.plies));
    section.ply_radius = s / (1.0f + s);
    section.ply_offset = 1.0f - section.ply_radius;
  }
  const float helix_radius = section.plies >= 2 ? section.ply_offset : 1.0f;
  section.twist_rate = std::tan(yarn.twist_degrees() * std::numbers::pi_v<float> / 180.0f) / helix_radius;
  return section;
}

float FibreDensity(const YarnSection& section, glm::vec2 p, float phase) {
  const float distance = glm::length(p);
  if (distance > 1.0f) {
    if (section.fuzz <= 0.0f || distance > section.extent()) return 0.0f;
    return section.fuzz * kFibreDensityEpsilon * std::exp(-3.0f * (distance - 1.0f) / section.fuzz);
  }
  // The plies do not overlap: the nearest centre is the only one p can be inside.
  const float step = 2.0f * std::numbers::pi_v<float> / static_cast<float>(section.plies);
  const float angle = std::atan2(p.y, p.x) - phase;
  const float nearest = step * std::round(angle / step) + phase;
  const glm::vec2 centre = section.ply_offset * glm::vec2(std::cos(nearest), std::sin(nearest));
  return PlyFibreDensity(glm::length(p - centre) / section.ply_radius);
}

std::vector<float> SectionDensityGrid(const YarnSection& section, int resolution) {
  std::vector<float> grid(static_cast<size_t>(resolution) * resolution, 0.0f);
  const float cell = 2.0f * section.extent() / static_cast<float>(resolution);
  for (int y = 0; y < resolution; ++y) {
    for (int x = 0; x < resolution; ++x) {
      float sum = 0.0f;
      for (int j = 0; j < kCellPoints; ++j) {
        for (int i = 0; i < kCellPoints; ++i) {
          const glm::vec2 p(-section.extent() + cell * (static_cast<float>(x) + (i + 0.5f) / kCellPoints),
                            -section.extent() + cell * (static_cast<float>(y) + (j + 0.5f) / kCellPoints));
          sum += FibreDensity(section, p);
        }
      }
      grid[static_cast<size_t>(y) * resolution + x] = sum / (kCellPoints * kCellPoints);
    }
  }
  return grid;
}

}  // namespace loom
