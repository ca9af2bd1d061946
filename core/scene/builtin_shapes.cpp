#include "core/scene/builtin_shapes.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

namespace loom {
namespace {

// A (segments_u + 1) x (segments_v + 1) vertex grid from a parametric surface;
// `surface(u, v, position, normal, tangent)` fills one vertex. With `poles`, the
// first and last vertex rows each collapse to a point (a sphere's poles): their
// quads are triangles, since the half with two vertices on the pole has no area.
template <typename Surface>
TriangleMesh MakeGrid(int segments_u, int segments_v, Surface surface, bool poles = false) {
  segments_u = std::max(segments_u, 1);
  segments_v = std::max(segments_v, 1);
  TriangleMesh mesh;
  for (int j = 0; j <= segments_v; ++j) {
    for (int i = 0; i <= segments_u; ++i) {
      const glm::vec2 uv(static_cast<float>(i) / segments_u, static_cast<float>(j) / segments_v);
      glm::vec3 position, normal, tangent;
      surface(uv.x, uv.y, position, normal, tangent);
      mesh.positions.push_back(position);
      mesh.normals.push_back(normal);
      mesh.uvs.push_back(uv);
      mesh.tangents.emplace_back(tangent, 1.0f);
    }
  }
  const uint32_t row = static_cast<uint32_t>(segments_u) + 1;
  for (uint32_t j = 0; j < static_cast<uint32_t>(segments_v); ++j) {
    for (uint32_t i = 0; i < static_cast<uint32_t>(segments_u); ++i) {
      const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
      if (!(poles && j == 0)) mesh.indices.insert(mesh.indices.end(), {a, b, d});
      if (!(poles && j + 1 == static_cast<uint32_t>(segments_v))) mesh.indices.insert(mesh.indices.end(), {a, d, c});
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh MakePlane(int segments) {
  return MakeGrid(segments, segments, [](float u, float v, glm::vec3& p, glm::vec3& n, glm::vec3& t) {
    p = {u - 0.5f, v - 0.5f, 0.0f};
    n = {0.0f, 0.0f, 1.0f};
    t = {1.0f, 0.0f, 0.0f};
  });
}

TriangleMesh MakeSphere(int segments) {
  // Two rings at least: with one, both poles' triangles would be all there is, and none has an area.
  segments = std::max(segments, 2);
  return MakeGrid(
      2 * segments, segments,
      [](float u, float v, glm::vec3& p, glm::vec3& n, glm::vec3& t) {
        const float phi = glm::two_pi<float>() * u;
        const float theta = glm::pi<float>() * (1.0f - v);  // from the north pole
        n = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
        p = n;
        t = {-std::sin(phi), std::cos(phi), 0.0f};
      },
      /*poles=*/true);
}

TriangleMesh MakeCylinder(int segments) {
  return MakeGrid(2 * segments, 1, [](float u, float v, glm::vec3& p, glm::vec3& n, glm::vec3& t) {
    const float phi = glm::two_pi<float>() * u;
    n = {std::cos(phi), std::sin(phi), 0.0f};
    p = {n.x, n.y, v - 0.5f};
    t = {-std::sin(phi), std::cos(phi), 0.0f};
  });
}

TriangleMesh MakeDrape(int segments) {
  constexpr float kRadius = 0.5f;
  constexpr float kEquatorArc = kRadius * glm::half_pi<float>();  // arc length from the top to the equator
  constexpr int kFolds = 8;
  TriangleMesh mesh = MakeGrid(segments, segments, [](float u, float v, glm::vec3& p, glm::vec3& n, glm::vec3& t) {
    // Flat cloth coordinates in [-1, 1]²; s is the arc length from the centre.
    const glm::vec2 flat(2.0f * u - 1.0f, 2.0f * v - 1.0f);
    const float s = glm::length(flat);
    const float phi = std::atan2(flat.y, flat.x);
    const glm::vec2 radial(std::cos(phi), std::sin(phi));
    if (s <= kEquatorArc) {
      const float theta = s / kRadius;
      p = glm::vec3(kRadius * std::sin(theta) * radial, kRadius * std::cos(theta));
    } else {
      const float hang = s - kEquatorArc;
      // Folds bulge outwards only: the cloth never cuts into the sphere below the equator.
      const float fold = 0.06f * hang * (1.0f + std::sin(kFolds * phi));
      p = glm::vec3((kRadius + fold) * radial, -hang);
    }
    n = glm::vec3(0.0f);  // filled in by PrepareMesh from the faces
    t = glm::vec3(0.0f);
  });
  mesh.normals.clear();
  mesh.tangents.clear();
  return mesh;
}

}  // namespace loom
