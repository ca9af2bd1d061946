#include "core/scene/mesh_preparation.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/util/error.h"

namespace loom {
namespace {

// A unit vector perpendicular to n, continuous over most of the sphere.
glm::vec3 AnyPerpendicular(const glm::vec3& n) {
  const glm::vec3 axis = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  return glm::normalize(axis - n * glm::dot(n, axis));
}

// Drops triangles with (relative) zero area; throws on indices out of range.
size_t DropDegenerateTriangles(TriangleMesh& mesh, const char* source) {
  Bounds bounds;
  bounds.Add(mesh.positions);
  const float diagonal = bounds.diagonal();
  // Twice the area below this counts as zero: ~1e-12 of the bounding box's face.
  const float min_double_area = 1e-12f * diagonal * diagonal;

  std::vector<uint32_t> kept;
  kept.reserve(mesh.indices.size());
  size_t dropped = 0;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    if (std::max({a, b, c}) >= mesh.positions.size()) {
      throw Error(ErrorCode::kInvalidArgument, std::string("mesh ") + source + ": triangle " +
                                                   std::to_string(t / 3) + " indexes a vertex that does not exist");
    }
    const glm::vec3 cross = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    if (!(glm::length(cross) > min_double_area)) {
      ++dropped;
      continue;
    }
    kept.insert(kept.end(), {a, b, c});
  }
  mesh.indices = std::move(kept);
  return dropped;
}

void ComputeMissingNormals(TriangleMesh& mesh) {
  const bool have_normals = mesh.normals.size() == mesh.positions.size();
  std::vector<glm::vec3> face_sum(mesh.positions.size(), glm::vec3(0.0f));
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    // The cross product's length is twice the area: an area-weighted sum.
    const glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    for (uint32_t v : {a, b, c}) face_sum[v] += n;
  }
  mesh.normals.resize(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 given = have_normals ? mesh.normals[v] : glm::vec3(0.0f);
    const glm::vec3 chosen = glm::length(given) > 1e-20f ? given : face_sum[v];
    mesh.normals[v] = glm::length(chosen) > 1e-20f ? glm::normalize(chosen) : glm::vec3(0, 0, 1);
  }
}

}  // namespace

MeshPreparationReport PrepareMesh(TriangleMesh& mesh, const char* source) {
  MeshPreparationReport report;
  const bool parameterised = !mesh.uvs.empty();
  if (!parameterised) mesh.uvs.assign(mesh.positions.size(), glm::vec2(0.0f));
  if (mesh.uvs.size() != mesh.positions.size()) {
    throw Error(ErrorCode::kInvalidArgument, std::string("mesh ") + source + ": every vertex needs a uv");
  }
  report.dropped_degenerate_triangles = DropDegenerateTriangles(mesh, source);
  if (mesh.indices.empty()) {
    throw Error(ErrorCode::kInvalidArgument,
                std::string("mesh ") + source + ": no triangle has a non-zero area");
  }
  if (report.dropped_degenerate_triangles > 0) {
    spdlog::warn("mesh {}: dropped {} degenerate triangle(s)", source, report.dropped_degenerate_triangles);
  }
  ComputeMissingNormals(mesh);

  // Tangent (∂p/∂u) and bitangent (∂p/∂v) per triangle from the UV Jacobian,
  // accumulated per vertex (Lengyel's method).
  std::vector<glm::vec3> du(mesh.positions.size(), glm::vec3(0.0f)), dv(mesh.positions.size(), glm::vec3(0.0f));
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::vec3 e1 = mesh.positions[b] - mesh.positions[a], e2 = mesh.positions[c] - mesh.positions[a];
    const glm::vec2 s1 = mesh.uvs[b] - mesh.uvs[a], s2 = mesh.uvs[c] - mesh.uvs[a];
    const float det = s1.x * s2.y - s1.y * s2.x;
    const float scale = std::max(glm::length(s1), glm::length(s2));
    if (!(std::abs(det) > 1e-12f * scale * scale)) {
      ++report.zero_area_uv_triangles;
      continue;
    }
    const glm::vec3 tangent = (e1 * s2.y - e2 * s1.y) / det;
    const glm::vec3 bitangent = (e2 * s1.x - e1 * s2.x) / det;
    for (uint32_t v : {a, b, c}) {
      du[v] += tangent;
      dv[v] += bitangent;
    }
  }
  mesh.tangents.resize(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3& n = mesh.normals[v];
    glm::vec3 t = du[v] - n * glm::dot(n, du[v]);
    if (!(glm::length(t) > 1e-12f) || !std::isfinite(t.x + t.y + t.z)) {
      t = AnyPerpendicular(n);
      ++report.fallback_tangents;
    }
    t = glm::normalize(t);
    const float handedness = glm::dot(glm::cross(n, t), dv[v]) < 0.0f ? -1.0f : 1.0f;
    mesh.tangents[v] = glm::vec4(t, handedness);
  }
  if (!parameterised) report.zero_area_uv_triangles = report.fallback_tangents = 0;  // nothing to tile
  if (report.zero_area_uv_triangles > 0) {
    spdlog::warn("mesh {}: {} triangle(s) with zero UV area (the fabric is squashed there)", source,
                 report.zero_area_uv_triangles);
  }
  return report;
}

}  // namespace loom
