#include "core/fabric/tube_mesh.h"

#include <cassert>
#include <cmath>
#include <numbers>

namespace loom {
namespace {

// Rotates v, perpendicular to the unit axis, about the axis by angle.
glm::vec3 RotateAbout(glm::vec3 v, glm::vec3 axis, float angle) {
  return std::cos(angle) * v + std::sin(angle) * glm::cross(axis, v);
}

}  // namespace

std::vector<glm::vec3> PeriodicFrameUp(const PeriodicYarn& yarn) {
  const std::vector<glm::vec3>& p = yarn.points;
  const std::vector<glm::vec3>& t = yarn.tangents;
  const size_t n = p.size();
  assert(n >= 2 && t.size() == n);
  std::vector<glm::vec3> up(n);
  glm::vec3 start = glm::vec3(0, 0, 1) - t[0].z * t[0];
  if (glm::dot(start, start) < 1e-6f) start = glm::vec3(1, 0, 0) - t[0].x * t[0];
  up[0] = glm::normalize(start);
  // Double reflection: reflect the frame in the bisector plane of the chord, then in
  // the plane that takes the reflected tangent onto the next tangent.
  std::vector<float> arc(n, 0.0f);
  for (size_t i = 0; i + 1 < n; ++i) {
    const glm::vec3 v1 = p[i + 1] - p[i];
    const float c1 = glm::dot(v1, v1);
    arc[i + 1] = arc[i] + std::sqrt(c1);
    glm::vec3 u = up[i], tl = t[i];
    if (c1 > 0) {
      u -= (2.0f / c1) * glm::dot(v1, u) * v1;
      tl -= (2.0f / c1) * glm::dot(v1, tl) * v1;
    }
    const glm::vec3 v2 = t[i + 1] - tl;
    const float c2 = glm::dot(v2, v2);
    if (c2 > 0) u -= (2.0f / c2) * glm::dot(v2, u) * v2;
    // Re-orthogonalise against float drift.
    up[i + 1] = glm::normalize(u - glm::dot(u, t[i + 1]) * t[i + 1]);
  }
  // The holonomy: the angle about the (shared) end tangent from the transported last
  // frame back to the first. Spread it along the yarn by arc length.
  const glm::vec3 last = up[n - 1];
  const float holonomy = std::atan2(glm::dot(t[0], glm::cross(last, up[0])), glm::dot(last, up[0]));
  for (size_t i = 1; i + 1 < n; ++i) up[i] = RotateAbout(up[i], t[i], holonomy * arc[i] / arc[n - 1]);
  up[n - 1] = up[0];
  return up;
}

void AppendTubeMesh(const PeriodicYarn& yarn, glm::vec3 model_to_tile, int ring_vertices,
                    std::span<const float> twist_radians, TriangleMesh& mesh, std::vector<uint32_t>& triangle_yarn) {
  const size_t n = yarn.points.size();
  const std::vector<glm::vec3> up = PeriodicFrameUp(yarn);
  const glm::vec3 tile_to_model = 1.0f / model_to_tile;  // normals transform by the inverse
  const uint32_t columns = static_cast<uint32_t>(ring_vertices) + 1;  // seam duplicated
  const uint32_t base = static_cast<uint32_t>(mesh.positions.size());

  float u = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    if (i > 0) u += glm::length(yarn.points[i] - yarn.points[i - 1]);
    const bool closing = i + 1 == n;
    const size_t at = closing ? 0 : i;
    const glm::vec3 centre = yarn.points[at];
    const glm::vec3 tangent = yarn.tangents[at];
    const glm::vec3 thickness_axis = up[at];
    const glm::vec3 width_axis = glm::cross(tangent, thickness_axis);
    const glm::vec2 section = yarn.section[at];
    const uint32_t yarn_index = yarn.segment_yarn[std::min(at, yarn.segment_yarn.size() - 1)];
    const float twist = twist_radians[yarn_index];
    for (uint32_t k = 0; k < columns; ++k) {
      const float angle = 2.0f * std::numbers::pi_v<float> * static_cast<float>(k % ring_vertices) /
                          static_cast<float>(ring_vertices);
      const SectionPoint boundary = SectionBoundary(yarn.shape, section, angle);
      const glm::vec3 position = centre + boundary.offset.x * width_axis + boundary.offset.y * thickness_axis;
      const glm::vec3 normal = boundary.normal.x * width_axis + boundary.normal.y * thickness_axis;
      // Direction of increasing angle (v): the section's tangent, perpendicular to its normal.
      const glm::vec3 around = -boundary.normal.y * width_axis + boundary.normal.x * thickness_axis;
      const glm::vec3 fibre = std::cos(twist) * tangent + std::sin(twist) * glm::cross(tangent, normal);
      const float handedness = glm::dot(glm::cross(normal, fibre), around) >= 0 ? 1.0f : -1.0f;
      // The closing ring is the first ring moved by the period.
      mesh.positions.push_back(closing ? mesh.positions[base + k] + yarn.period * model_to_tile
                                       : position * model_to_tile);
      mesh.normals.push_back(glm::normalize(normal * tile_to_model));
      mesh.tangents.emplace_back(glm::normalize(fibre * model_to_tile), handedness);
      mesh.uvs.emplace_back(u, static_cast<float>(k) / static_cast<float>(ring_vertices));
    }
  }
  // Quads between consecutive rings, wound counter-clockwise seen from outside.
  for (uint32_t i = 0; i + 1 < n; ++i) {
    for (uint32_t k = 0; k < static_cast<uint32_t>(ring_vertices); ++k) {
      const uint32_t a = base + i * columns + k, b = a + 1, d = a + columns, c = d + 1;
      mesh.indices.insert(mesh.indices.end(), {a, d, b, b, d, c});
      triangle_yarn.insert(triangle_yarn.end(), 2, yarn.segment_yarn[i]);
    }
  }
}

}  // namespace loom
