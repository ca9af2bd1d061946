#include "core/fabric/yarn_volume.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include "core/util/error.h"
#include "core/util/vector_math.h"

namespace loom {
namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
// Grid cells per side of the tile: a cell about a third of a yarn radius for the usual
// 0.07 loop-width yarns in a tile of one or two loops.
constexpr int kMaxGridCells = 96;
constexpr float kCellsPerModelUnit = 48.0f;
// March steps per radius of the thinnest ply.
constexpr float kStepsPerPlyRadius = 6.0f;

}  // namespace

bool HasYarnVolume(const v1::FabricSpec& fabric) {
  if (!fabric.has_knit()) return false;
  return std::any_of(fabric.yarns().begin(), fabric.yarns().end(),
                     [](const v1::YarnSpec& yarn) { return yarn.plies() > 1 || yarn.fuzz() > 0.0f; });
}

YarnVolume::YarnVolume(const TileYarns& yarns, const v1::FabricSpec& fabric) : model_to_tile_(yarns.model_to_tile) {
  period_ = glm::vec2(1.0f) / glm::vec2(model_to_tile_);
  float reach_max = 0.0f, ply_min = 1e30f;
  for (const v1::YarnSpec& yarn : fabric.yarns()) {
    sections_.push_back(MakeYarnSection(yarn));
    radius_.push_back(yarn.radius());
    reach_max = std::max(reach_max, sections_.back().extent() * yarn.radius());
    ply_min = std::min(ply_min, sections_.back().ply_radius * yarn.radius());
  }
  step_ = ply_min / kStepsPerPlyRadius * model_to_tile_.x;

  z_min_ = 1e30f;
  z_max_ = -1e30f;
  for (const PeriodicYarn& yarn : yarns.yarns) {
    // The grid joins each course to its copy one tile along x (a knit's courses).
    if (std::abs(yarn.period.x - period_.x) > 1e-4f * period_.x || yarn.period.y != 0.0f || yarn.points.size() < 2) {
      throw Error(ErrorCode::kInternal, "yarn volume: a yarn does not span the tile once along x");
    }
    Chain chain;
    chain.points = yarn.points;
    chain.segment_yarn = yarn.segment_yarn;
    const size_t n = chain.points.size();
    // Normals transported along the line (each the last projected off the next tangent).
    chain.normals.resize(n);
    chain.normals[0] = AnyPerpendicular(yarn.tangents[0]);
    for (size_t i = 1; i < n; ++i) {
      const glm::vec3 t = yarn.tangents[i], previous = chain.normals[i - 1];
      const glm::vec3 projected = previous - t * glm::dot(previous, t);
      chain.normals[i] = glm::length(projected) > 1e-6f ? glm::normalize(projected) : AnyPerpendicular(t);
    }
    // The section's turn: each yarn's twist rate, then an even correction so that the
    // periodic copy that follows carries on seamlessly (its normal differs from the
    // transported one by the holonomy δ; the turn at the end must be δ modulo a turn).
    chain.turn.assign(n, 0.0f);
    for (size_t i = 0; i + 1 < n; ++i) {
      const uint32_t y = chain.segment_yarn[i];
      const float length = glm::length(chain.points[i + 1] - chain.points[i]);
      chain.turn[i + 1] = chain.turn[i] + (sections_[y].twist_rate / radius_[y]) * length;
    }
    float total_length = 0.0f;
    for (size_t i = 0; i + 1 < n; ++i) total_length += glm::length(chain.points[i + 1] - chain.points[i]);
    const glm::vec3 t0 = yarn.tangents[0], n_end = chain.normals[n - 1], n0 = chain.normals[0];
    const float holonomy = std::atan2(glm::dot(glm::cross(n_end, n0), t0), glm::dot(n_end, n0));
    const float turns = std::round((chain.turn[n - 1] - holonomy) / kTwoPi);
    const float correction = (holonomy + kTwoPi * turns - chain.turn[n - 1]) / std::max(total_length, 1e-6f);
    float arc = 0.0f;
    for (size_t i = 1; i < n; ++i) {
      arc += glm::length(chain.points[i] - chain.points[i - 1]);
      chain.turn[i] += correction * arc;
    }
    for (size_t i = 0; i + 1 < n; ++i) {
      const float reach = sections_[chain.segment_yarn[i]].extent() * radius_[chain.segment_yarn[i]];
      z_min_ = std::min(z_min_, std::min(chain.points[i].z, chain.points[i + 1].z) - reach);
      z_max_ = std::max(z_max_, std::max(chain.points[i].z, chain.points[i + 1].z) + reach);
    }
    chains_.push_back(std::move(chain));
  }
  z_min_ *= model_to_tile_.z;
  z_max_ *= model_to_tile_.z;

  // The grid: each cell lists the segments (in every periodic copy) that come within a
  // yarn's reach of it, in chain, copy and segment order.
  grid_ = std::clamp(static_cast<int>(std::ceil(std::max(period_.x, period_.y) * kCellsPerModelUnit)), 1, kMaxGridCells);
  const glm::vec2 cell = period_ / static_cast<float>(grid_);
  std::vector<std::vector<Entry>> cells(static_cast<size_t>(grid_) * grid_);
  for (uint32_t c = 0; c < chains_.size(); ++c) {
    const Chain& chain = chains_[c];
    glm::vec2 low(1e30f), high(-1e30f);
    for (const glm::vec3& p : chain.points) {
      low = glm::min(low, glm::vec2(p));
      high = glm::max(high, glm::vec2(p));
    }
    low -= reach_max;
    high += reach_max;
    const glm::ivec2 first(glm::floor(-high / period_)), last(glm::ceil((period_ - low) / period_));
    // A knit course spans the tile in x: its copy shifted by one tile in x follows it.
    const int64_t segments = static_cast<int64_t>(chain.points.size() - 1);
    for (int sy = first.y; sy <= last.y; ++sy) {
      for (int sx = first.x; sx <= last.x; ++sx) {
        const glm::vec2 shift = glm::vec2(sx, sy) * period_;
        for (uint32_t i = 0; i + 1 < chain.points.size(); ++i) {
          const float reach = sections_[chain.segment_yarn[i]].extent() * radius_[chain.segment_yarn[i]];
          const glm::vec2 a = glm::vec2(chain.points[i]) + shift, b = glm::vec2(chain.points[i + 1]) + shift;
          const glm::vec2 box_low = glm::min(a, b) - reach, box_high = glm::max(a, b) + reach;
          if (box_high.x < 0.0f || box_high.y < 0.0f || box_low.x >= period_.x || box_low.y >= period_.y) continue;
          const glm::ivec2 from = glm::clamp(glm::ivec2(glm::floor(box_low / cell)), 0, grid_ - 1);
          const glm::ivec2 to = glm::clamp(glm::ivec2(glm::floor(box_high / cell)), 0, grid_ - 1);
          for (int y = from.y; y <= to.y; ++y) {
            for (int x = from.x; x <= to.x; ++x) {
              cells[static_cast<size_t>(y) * grid_ + x].push_back({c, i, shift, sy, sx * segments + i});
            }
          }
        }
      }
    }
  }
  cell_begin_.reserve(cells.size() + 1);
  cell_begin_.push_back(0);
  for (std::vector<Entry>& list : cells) {
    std::sort(list.begin(), list.end(), [](const Entry& a, const Entry& b) {
      return std::tie(a.chain, a.across, a.along) < std::tie(b.chain, b.across, b.along);
    });
    entries_.insert(entries_.end(), list.begin(), list.end());
    cell_begin_.push_back(static_cast<uint32_t>(entries_.size()));
  }
}

VolumeSample YarnVolume::Sample(glm::vec3 p) const {
  glm::vec3 m = p / model_to_tile_;
  m.x -= std::floor(m.x / period_.x) * period_.x;
  m.y -= std::floor(m.y / period_.y) * period_.y;
  const glm::ivec2 cell = glm::clamp(glm::ivec2(glm::vec2(m) / period_ * static_cast<float>(grid_)), 0, grid_ - 1);
  const uint32_t begin = cell_begin_[static_cast<size_t>(cell.y) * grid_ + cell.x];
  const uint32_t end = cell_begin_[static_cast<size_t>(cell.y) * grid_ + cell.x + 1];

  VolumeSample sample;
  float densest = 0.0f;
  // Each run of consecutive segments of a chain (running on into its next periodic copy)
  // is one stretch of yarn near the point: its nearest point is where the point lies in
  // that yarn's section.
  uint32_t i = begin;
  while (i < end) {
    const Entry& first = entries_[i];
    const Chain& chain = chains_[first.chain];
    float best = 1e30f, best_u = 0.0f;
    uint32_t best_segment = first.segment;
    glm::vec3 shift = glm::vec3(first.shift, 0.0f);
    uint32_t j = i;
    for (; j < end; ++j) {
      const Entry& entry = entries_[j];
      if (j > i && (entry.chain != first.chain || entry.across != first.across || entry.along != entries_[j - 1].along + 1)) break;
      const glm::vec3 entry_shift(entry.shift, 0.0f);
      const glm::vec3 a = chain.points[entry.segment] + entry_shift, ab = chain.points[entry.segment + 1] - chain.points[entry.segment];
      const float u = std::clamp(glm::dot(m - a, ab) / std::max(glm::dot(ab, ab), 1e-20f), 0.0f, 1.0f);
      const glm::vec3 d = m - (a + u * ab);
      const float distance2 = glm::dot(d, d);
      if (distance2 < best) {
        best = distance2;
        best_u = u;
        best_segment = entry.segment;
        shift = entry_shift;
      }
    }
    i = j;
    const uint32_t yarn = chain.segment_yarn[best_segment];
    const YarnSection& section = sections_[yarn];
    const float radius = radius_[yarn];
    if (best > section.extent() * section.extent() * radius * radius) continue;

    const glm::vec3 a = chain.points[best_segment] + shift, b = chain.points[best_segment + 1] + shift;
    const glm::vec3 centre = a + best_u * (b - a);
    const glm::vec3 t = glm::normalize(b - a);
    glm::vec3 normal = glm::mix(chain.normals[best_segment], chain.normals[best_segment + 1], best_u);
    normal = glm::normalize(normal - t * glm::dot(normal, t));
    const glm::vec3 binormal = glm::cross(t, normal);
    const glm::vec3 d = m - centre;
    const float turn = chain.turn[best_segment] + best_u * (chain.turn[best_segment + 1] - chain.turn[best_segment]);
    const float density = FibreDensity(section, glm::vec2(glm::dot(d, normal), glm::dot(d, binormal)) / radius, turn);
    if (density <= 0.0f) continue;
    const float extinction = kYarnOpticalDensity * density / radius;
    sample.extinction += extinction;
    if (extinction > densest) {
      densest = extinction;
      sample.material = yarn;
      // The fibres turn with the section: a point at d from the centre line moves
      // across it at rate k·|d| as it runs along it.
      const glm::vec3 fibre = t + (section.twist_rate / radius) * glm::cross(t, d);
      sample.fibre = glm::normalize(fibre * model_to_tile_);
    }
  }
  return sample;
}

}  // namespace loom
