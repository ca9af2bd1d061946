#include "yarn_clearance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/fabric/tube_mesh.h"

namespace loom {
namespace {

struct Sample {
  glm::vec3 p, width_axis, thickness_axis;
  glm::vec2 section;
  float arc;
};

std::vector<Sample> Samples(const PeriodicYarn& yarn) {
  const std::vector<glm::vec3> up = PeriodicFrameUp(yarn);
  std::vector<Sample> samples;
  float arc = 0.0f;
  for (size_t i = 0; i < yarn.points.size(); ++i) {
    if (i > 0) arc += glm::length(yarn.points[i] - yarn.points[i - 1]);
    samples.push_back({yarn.points[i], glm::cross(yarn.tangents[i], up[i]), up[i], yarn.section[i], arc});
  }
  return samples;
}

// The extent of a cross-section from its centre along unit direction d.
float Support(const Sample& s, glm::vec3 d) {
  const float w = s.section.x * glm::dot(d, s.width_axis), t = s.section.y * glm::dot(d, s.thickness_axis);
  return std::sqrt(w * w + t * t);
}

// The factor by which the section must be scaled about its centre for its boundary to
// pass through (u, v): below 1 inside.
float SectionGauge(SectionShape shape, glm::vec2 half_extent, glm::vec2 uv) {
  const float a = half_extent.x, b = half_extent.y, u = std::abs(uv.x), v = std::abs(uv.y);
  if (shape == SectionShape::kEllipse) return std::sqrt((u / a) * (u / a) + (v / b) * (v / b));
  // Scaled lens: v = s b - u² b / (s a²), solved for s.
  return (v + std::sqrt(v * v + 4 * b * b * u * u / (a * a))) / (2 * b);
}

// Whether yarn b moved by `shift` is yarn a itself a whole number of periods on
// (the same thread, whose nearby points are neighbours along it, not a crossing),
// and by how many periods.
struct ThreadCopy {
  bool same = false;
  float periods = 0.0f;
};

ThreadCopy SameThreadCopy(const TileYarns& tile, size_t a, size_t b, glm::vec3 shift) {
  if (a != b) return {};
  const glm::vec3 period = tile.yarns[b].period;
  const float along = glm::dot(shift, period) / glm::dot(period, period);
  return {glm::length(shift - along * period) < 1e-4f * glm::length(period), along};
}

// Every yarn's dense centre samples, the tile's size in model space and the
// largest cross-section extent: what both clearance measures start from.
struct SampledTile {
  glm::vec3 tile_size;
  std::vector<std::vector<Sample>> yarns;
  float max_extent = 0.0f;
};

SampledTile SampleTile(const TileYarns& tile) {
  SampledTile sampled{1.0f / tile.model_to_tile, {}, 0.0f};
  for (const PeriodicYarn& yarn : tile.yarns) {
    sampled.yarns.push_back(Samples(yarn));
    for (glm::vec2 s : yarn.section) sampled.max_extent = std::max({sampled.max_extent, s.x, s.y});
  }
  return sampled;
}

}  // namespace

Clearance MeasureClearance(const TileYarns& tile) {
  const auto [tile_size, yarns, max_extent] = SampleTile(tile);
  Clearance best;
  best.ratio = std::numeric_limits<float>::infinity();
  for (size_t a = 0; a < yarns.size(); ++a) {
    const std::vector<Sample>& sa = yarns[a];
    for (size_t b = 0; b < yarns.size(); ++b) {
      const std::vector<Sample>& sb = yarns[b];
      const float period_length = sb.back().arc;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const glm::vec3 shift(dx * tile_size.x, dy * tile_size.y, 0.0f);
          const ThreadCopy copy = SameThreadCopy(tile, a, b, shift);
          const bool same = copy.same;
          const float periods = copy.periods;
          for (size_t i = 0; i + 1 < sa.size(); ++i) {
            const Sample& p = sa[i];
            for (size_t j = 0; j + 1 < sb.size(); ++j) {
              const glm::vec3 q0 = sb[j].p + shift, q1 = sb[j + 1].p + shift;
              // Pairs farther apart than the best ratio allows cannot improve it.
              const glm::vec3 mid = 0.5f * (q0 + q1);
              const float reach = 0.5f * glm::length(q1 - q0) + 2.0f * max_extent * std::min(best.ratio, 4.0f);
              const glm::vec3 gap = glm::abs(p.p - mid);
              if (gap.x > reach || gap.y > reach || gap.z > reach) continue;
              const glm::vec3 seg = q1 - q0;
              const float len2 = glm::dot(seg, seg);
              const float t = len2 > 0 ? std::clamp(glm::dot(p.p - q0, seg) / len2, 0.0f, 1.0f) : 0.0f;
              const Sample& q = t < 0.5f ? sb[j] : sb[j + 1];
              if (same) {
                const float arc_q = sb[j].arc + t * (sb[j + 1].arc - sb[j].arc) + periods * period_length;
                const float exclusion = std::numbers::pi_v<float> * std::max({p.section.x, p.section.y, q.section.x, q.section.y});
                if (std::abs(arc_q - p.arc) < exclusion) continue;
              }
              const glm::vec3 closest = q0 + t * seg;
              const glm::vec3 delta = closest - p.p;
              const float distance = glm::length(delta);
              const glm::vec3 d = distance > 0 ? delta / distance : glm::vec3(0, 0, 1);
              const float ratio = distance / (Support(p, d) + Support(q, d));
              if (ratio < best.ratio) best = {ratio, 0.5f * (p.p + closest), a, b};
            }
          }
        }
      }
    }
  }
  return best;
}

Clearance SurfaceClearance(const TileYarns& tile, int ring_vertices) {
  const auto [tile_size, yarns, max_extent] = SampleTile(tile);
  Clearance best;
  best.ratio = std::numeric_limits<float>::infinity();
  for (size_t a = 0; a < yarns.size(); ++a) {
    for (size_t i = 0; i + 1 < yarns[a].size(); ++i) {
      const Sample& centre = yarns[a][i];
      for (int k = 0; k < ring_vertices; ++k) {
        const float angle = 2.0f * std::numbers::pi_v<float> * static_cast<float>(k) / static_cast<float>(ring_vertices);
        const glm::vec2 offset = SectionBoundary(tile.yarns[a].shape, centre.section, angle).offset;
        const glm::vec3 p = centre.p + offset.x * centre.width_axis + offset.y * centre.thickness_axis;
        for (size_t b = 0; b < yarns.size(); ++b) {
          const std::vector<Sample>& sb = yarns[b];
          const float period_length = sb.back().arc;
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              const glm::vec3 shift(dx * tile_size.x, dy * tile_size.y, 0.0f);
              const ThreadCopy copy = SameThreadCopy(tile, a, b, shift);
              const bool same = copy.same;
              const float periods = copy.periods;
              for (size_t j = 0; j + 1 < sb.size(); ++j) {
                const glm::vec3 q0 = sb[j].p + shift, q1 = sb[j + 1].p + shift;
                const glm::vec3 seg = q1 - q0;
                const float len2 = glm::dot(seg, seg);
                const glm::vec3 gap = glm::abs(p - 0.5f * (q0 + q1));
                const float reach = 0.5f * std::sqrt(len2) + max_extent;
                if (gap.x > reach || gap.y > reach || gap.z > reach || len2 <= 0) continue;
                // Only a section whose normal plane contains p can contain it.
                const float t = glm::dot(p - q0, seg) / len2;
                if (t < 0 || t > 1) continue;
                if (same) {
                  const float arc_q = sb[j].arc + t * (sb[j + 1].arc - sb[j].arc) + periods * period_length;
                  const float exclusion = std::numbers::pi_v<float> * max_extent;
                  if (std::abs(arc_q - centre.arc) < exclusion) continue;
                }
                const Sample& q = t < 0.5f ? sb[j] : sb[j + 1];
                const glm::vec3 local = p - (q0 + t * seg);
                const float norm = SectionGauge(tile.yarns[b].shape, q.section,
                                                glm::vec2(glm::dot(local, q.width_axis), glm::dot(local, q.thickness_axis)));
                if (norm < best.ratio) best = {norm, p, a, b};
              }
            }
          }
        }
      }
    }
  }
  return best;
}

float MinCurvatureRatio(const TileYarns& tile) {
  float best = std::numeric_limits<float>::infinity();
  for (const PeriodicYarn& yarn : tile.yarns) {
    for (size_t i = 1; i + 1 < yarn.points.size(); ++i) {
      // Radius of the circle through three consecutive samples.
      const glm::vec3 a = yarn.points[i - 1], b = yarn.points[i], c = yarn.points[i + 1];
      const float cross = glm::length(glm::cross(b - a, c - b));
      if (cross <= 0) continue;
      const float radius = glm::length(b - a) * glm::length(c - b) * glm::length(c - a) / (2.0f * cross);
      best = std::min(best, radius / std::max(yarn.section[i].x, yarn.section[i].y));
    }
  }
  return best;
}

}  // namespace loom
