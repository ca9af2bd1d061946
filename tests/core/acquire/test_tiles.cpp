#include "tests/core/acquire/test_tiles.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

namespace loom::testing {

YarnMaterial Lambertian(float albedo) {
  YarnMaterial material;
  material.diffuse_albedo = glm::vec3(albedo);
  material.specular_albedo = glm::vec3(0.0f);
  return material;
}

FabricTile FlatPatch(float z, const YarnMaterial& material) {
  FabricTile tile;
  tile.mesh.positions = {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}};
  tile.mesh.normals.assign(4, {0, 0, 1});
  tile.mesh.tangents.assign(4, {1, 0, 0, 1});
  tile.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  tile.mesh.indices = {0, 1, 2, 0, 2, 3};
  tile.triangle_material = {0, 0};
  tile.materials = {material};
  tile.z_min = tile.z_max = z;
  return tile;
}

FabricTile Tubes(const std::vector<Tube>& tubes, const YarnMaterial& material, uint32_t around, uint32_t along) {
  FabricTile tile;
  TriangleMesh& mesh = tile.mesh;
  tile.z_min = 1e30f;
  tile.z_max = -1e30f;
  for (const Tube& tube : tubes) {
    const auto first = static_cast<uint32_t>(mesh.positions.size());
    const glm::vec3 axis = tube.axis == Axis::kX ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 side = tube.axis == Axis::kX ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 centre = tube.offset * side + glm::vec3(0, 0, tube.height);
    for (uint32_t i = 0; i <= along; ++i) {
      for (uint32_t j = 0; j < around; ++j) {
        const float phi = glm::two_pi<float>() * static_cast<float>(j) / static_cast<float>(around);
        const glm::vec3 normal = std::cos(phi) * side + std::sin(phi) * glm::vec3(0, 0, 1);
        const glm::vec3 position = centre + axis * (static_cast<float>(i) / static_cast<float>(along)) + tube.radius * normal;
        mesh.positions.push_back(position);
        mesh.normals.push_back(normal);
        mesh.tangents.emplace_back(axis, 1.0f);
        mesh.uvs.emplace_back(static_cast<float>(i) / along, static_cast<float>(j) / around);
        tile.z_min = std::min(tile.z_min, position.z);
        tile.z_max = std::max(tile.z_max, position.z);
      }
    }
    for (uint32_t i = 0; i < along; ++i) {
      for (uint32_t j = 0; j < around; ++j) {
        const uint32_t a = first + i * around + j, b = first + i * around + (j + 1) % around;
        const uint32_t c = a + around, d = b + around;
        mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
      }
    }
  }
  tile.triangle_material.assign(mesh.triangle_count(), 0);
  tile.materials = {material};
  return tile;
}

FabricTile VGrooves(const YarnMaterial& material, uint32_t segments) {
  FabricTile tile;
  TriangleMesh& mesh = tile.mesh;
  // Two slopes, each its own vertices so that the normal is constant per slope.
  for (const float side : {-1.0f, 1.0f}) {  // −1: rising from y = 0, facing −y; +1: falling to y = 1
    const auto first = static_cast<uint32_t>(mesh.positions.size());
    const glm::vec3 normal = glm::normalize(glm::vec3(0, side, 1));
    for (uint32_t i = 0; i <= segments; ++i) {
      const float y = 0.5f * (side < 0 ? 0.0f : 1.0f) + 0.5f * static_cast<float>(i) / segments;
      const float z = side < 0 ? y : 1.0f - y;
      for (float x : {0.0f, 1.0f}) {
        mesh.positions.push_back({x, y, z});
        mesh.normals.push_back(normal);
        mesh.tangents.emplace_back(1, 0, 0, 1);
        mesh.uvs.emplace_back(x, y);
      }
    }
    for (uint32_t i = 0; i < segments; ++i) {
      const uint32_t a = first + 2 * i, b = a + 1, c = a + 2, d = a + 3;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
  tile.triangle_material.assign(mesh.triangle_count(), 0);
  tile.materials = {material};
  tile.z_min = 0.0f;
  tile.z_max = 0.5f;
  return tile;
}

FabricTile Merge(const FabricTile& a, const FabricTile& b) {
  FabricTile tile = a;
  const auto offset = static_cast<uint32_t>(a.mesh.positions.size());
  const auto material_offset = static_cast<uint32_t>(a.materials.size());
  auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
  append(tile.mesh.positions, b.mesh.positions);
  append(tile.mesh.normals, b.mesh.normals);
  append(tile.mesh.tangents, b.mesh.tangents);
  append(tile.mesh.uvs, b.mesh.uvs);
  for (uint32_t index : b.mesh.indices) tile.mesh.indices.push_back(index + offset);
  for (uint32_t material : b.triangle_material) tile.triangle_material.push_back(material + material_offset);
  append(tile.materials, b.materials);
  tile.z_min = std::min(a.z_min, b.z_min);
  tile.z_max = std::max(a.z_max, b.z_max);
  return tile;
}

}  // namespace loom::testing
