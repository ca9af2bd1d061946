#include "core/render/knit_skeleton.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/fabric/knit_tile.h"
#include "core/fabric/yarn_section.h"
#include "core/util/vector_math.h"

namespace loom {
namespace {

// Spline samples between a course's key points: as many as the tile's tubes have.
constexpr int kSamplesPerSegment = 8;

// The mesh's triangles in tile space (uv·repeat), found through a uniform grid.
class TileSpaceTriangles {
 public:
  TileSpaceTriangles(const TriangleMesh& mesh, glm::vec2 repeat) : mesh_(mesh), repeat_(repeat) {
    const size_t count = mesh.triangle_count();
    low_ = glm::vec2(1e30f);
    high_ = glm::vec2(-1e30f);
    for (const glm::vec2& uv : mesh.uvs) {
      low_ = glm::min(low_, uv * repeat);
      high_ = glm::max(high_, uv * repeat);
    }
    side_ = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(count))), 1, 1024);
    cell_ = glm::max((high_ - low_) / static_cast<float>(side_), glm::vec2(1e-6f));
    cells_.resize(static_cast<size_t>(side_) * side_);
    for (uint32_t t = 0; t < count; ++t) {
      glm::vec2 a(1e30f), b(-1e30f);
      for (int k = 0; k < 3; ++k) {
        const glm::vec2 p = Corner(t, k);
        a = glm::min(a, p);
        b = glm::max(b, p);
      }
      const glm::ivec2 c0 = Cell(a), c1 = Cell(b);
      for (int y = c0.y; y <= c1.y; ++y) {
        for (int x = c0.x; x <= c1.x; ++x) cells_[static_cast<size_t>(y) * side_ + x].push_back(t);
      }
    }
    // World length per tile unit along u, per triangle: |∂P/∂u| / repeat_u.
    scale_.resize(count);
    for (uint32_t t = 0; t < count; ++t) {
      const glm::vec2 e1 = Corner(t, 1) - Corner(t, 0), e2 = Corner(t, 2) - Corner(t, 0);
      const glm::vec3 p1 = Position(t, 1) - Position(t, 0), p2 = Position(t, 2) - Position(t, 0);
      const float det = e1.x * e2.y - e1.y * e2.x;
      // ∂P/∂x (x = u·repeat_u) from the triangle's Jacobian.
      scale_[t] = std::abs(det) > 1e-12f ? glm::length((p1 * e2.y - p2 * e1.y) / det) : 0.0f;
    }
  }

  glm::vec2 low() const { return low_; }
  glm::vec2 high() const { return high_; }

  struct Place {
    glm::vec3 position, normal;
    float scale;  // world units per tile unit along u
  };
  // Where tile-space point p lands on the mesh; none outside it.
  std::optional<Place> Map(glm::vec3 p) const {
    const glm::vec2 q(p);
    if (q.x < low_.x || q.y < low_.y || q.x > high_.x || q.y > high_.y) return std::nullopt;
    const glm::ivec2 c = Cell(q);
    for (const uint32_t t : cells_[static_cast<size_t>(c.y) * side_ + c.x]) {
      const glm::vec2 a = Corner(t, 0), e1 = Corner(t, 1) - a, e2 = Corner(t, 2) - a, d = q - a;
      const float det = e1.x * e2.y - e1.y * e2.x;
      if (std::abs(det) < 1e-12f) continue;
      const float b1 = (d.x * e2.y - d.y * e2.x) / det, b2 = (e1.x * d.y - e1.y * d.x) / det, b0 = 1.0f - b1 - b2;
      constexpr float kSlack = -1e-5f;
      if (b0 < kSlack || b1 < kSlack || b2 < kSlack || scale_[t] <= 0.0f) continue;
      const glm::vec3 position = b0 * Position(t, 0) + b1 * Position(t, 1) + b2 * Position(t, 2);
      const glm::vec3 normal = glm::normalize(b0 * Normal(t, 0) + b1 * Normal(t, 1) + b2 * Normal(t, 2));
      return Place{position + p.z * scale_[t] * normal, normal, scale_[t]};
    }
    return std::nullopt;
  }

 private:
  uint32_t Vertex(uint32_t t, int k) const { return mesh_.indices[3 * t + k]; }
  glm::vec2 Corner(uint32_t t, int k) const { return mesh_.uvs[Vertex(t, k)] * repeat_; }
  glm::vec3 Position(uint32_t t, int k) const { return mesh_.positions[Vertex(t, k)]; }
  glm::vec3 Normal(uint32_t t, int k) const { return mesh_.normals[Vertex(t, k)]; }
  glm::ivec2 Cell(glm::vec2 p) const {
    return glm::clamp(glm::ivec2((p - low_) / cell_), glm::ivec2(0), glm::ivec2(side_ - 1));
  }

  const TriangleMesh& mesh_;
  glm::vec2 repeat_;
  glm::vec2 low_, high_, cell_;
  int side_ = 1;
  std::vector<std::vector<uint32_t>> cells_;
  std::vector<float> scale_;
};

// Frames and turns along a placed chain (points, radius and segment_yarn set).
void FinishChain(SkeletonChain& chain, const std::vector<YarnSection>& sections) {
  const size_t n = chain.points.size();
  chain.normals.resize(n);
  chain.turn.assign(n, 0.0f);
  glm::vec3 previous(0.0f);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 t = glm::normalize(chain.points[std::min(i + 1, n - 1)] - chain.points[i > 0 ? i - 1 : 0]);
    const glm::vec3 projected = previous - t * glm::dot(previous, t);
    chain.normals[i] = glm::length(projected) > 1e-6f ? glm::normalize(projected) : AnyPerpendicular(t);
    previous = chain.normals[i];
    if (i + 1 < n) {
      const float length = glm::length(chain.points[i + 1] - chain.points[i]);
      const float radius = 0.5f * (chain.radius[i] + chain.radius[i + 1]);
      chain.turn[i + 1] = chain.turn[i] + sections[chain.segment_yarn[i]].twist_rate / radius * length;
    }
  }
}

}  // namespace

size_t KnitSkeleton::segment_count() const {
  size_t count = 0;
  for (const SkeletonChain& chain : chains) count += chain.segment_yarn.size();
  return count;
}

KnitSkeleton PlaceKnitSkeleton(const v1::FabricSpec& fabric, const TriangleMesh& mesh, glm::vec2 repeat) {
  const TileYarns yarns = BuildKnitYarns(fabric, kSamplesPerSegment);
  std::vector<YarnSection> sections;
  std::vector<float> tile_radius;
  for (const v1::YarnSpec& yarn : fabric.yarns()) {
    sections.push_back(MakeYarnSection(yarn));
    tile_radius.push_back(yarn.radius() * yarns.model_to_tile.x);
  }
  const TileSpaceTriangles triangles(mesh, repeat);
  KnitSkeleton skeleton;
  const int x0 = static_cast<int>(std::floor(triangles.low().x)) - 1;
  const int x1 = static_cast<int>(std::ceil(triangles.high().x)) + 1;
  const int y0 = static_cast<int>(std::floor(triangles.low().y)) - 1;
  const int y1 = static_cast<int>(std::ceil(triangles.high().y)) + 1;
  for (const PeriodicYarn& course : yarns.yarns) {
    const size_t n = course.points.size();
    for (int j = y0; j <= y1; ++j) {
      SkeletonChain chain;
      const auto close = [&] {
        if (chain.points.size() >= 2) {
          FinishChain(chain, sections);
          skeleton.chains.push_back(std::move(chain));
        }
        chain = SkeletonChain();
      };
      // The course's copies one tile apart in x continue each other: point n − 1 of one
      // is point 0 of the next.
      for (int i = x0; i <= x1; ++i) {
        for (size_t k = (i == x0 ? 0 : 1); k < n; ++k) {
          const glm::vec3 tile = course.points[k] * yarns.model_to_tile + glm::vec3(i, j, 0);
          const std::optional<TileSpaceTriangles::Place> place = triangles.Map(tile);
          const uint32_t yarn = course.segment_yarn[k > 0 ? k - 1 : 0];
          if (!place) {
            close();
            continue;
          }
          if (!chain.points.empty()) chain.segment_yarn.push_back(course.segment_yarn[k > 0 ? k - 1 : n - 2]);
          chain.points.push_back(place->position);
          chain.radius.push_back(tile_radius[yarn] * place->scale);
        }
      }
      close();
    }
  }
  return skeleton;
}

}  // namespace loom
