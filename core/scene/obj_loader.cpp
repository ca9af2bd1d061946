#include "core/scene/obj_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <map>
#include <tuple>

#include "core/spec/limits.h"
#include "core/util/error.h"

namespace loom {
namespace {

Error Invalid(const std::string& source, const std::string& what) {
  return Error(ErrorCode::kInvalidArgument, "mesh " + source + ": " + what);
}

// tinyobjloader reads the tokens "nan" and "inf" as 0 without a word; a mesh that
// spells them out is as broken as one that overflows to Inf, so say so.
bool SpellsOutNonFinite(std::string_view text) {
  std::istringstream lines{std::string(text)};
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != 'v') continue;
    std::istringstream tokens(line);
    std::string token;
    while (tokens >> token) {
      std::transform(token.begin(), token.end(), token.begin(), [](unsigned char c) { return std::tolower(c); });
      if (token.find("nan") != std::string::npos || token.find("inf") != std::string::npos) return true;
    }
  }
  return false;
}

}  // namespace

TriangleMesh ParseObj(std::string_view text, const std::string& source) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(std::string(text), "", config)) {
    throw Invalid(source, "not a valid OBJ file: " + reader.Error());
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();

  size_t triangles = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) triangles += shape.mesh.num_face_vertices.size();
  if (triangles == 0) throw Invalid(source, "has no faces");
  if (triangles > kMaxMeshTriangles) {
    throw Invalid(source, std::to_string(triangles) + " triangles exceeds " + std::to_string(kMaxMeshTriangles));
  }
  if (SpellsOutNonFinite(text)) throw Invalid(source, "contains a non-finite number (NaN or Inf)");
  if (attrib.texcoords.empty()) {
    throw Invalid(source, "has no texture coordinates (vt): a fabric is tiled over the mesh through its UVs");
  }
  for (const auto* values : {&attrib.vertices, &attrib.texcoords, &attrib.normals}) {
    for (const tinyobj::real_t value : *values) {
      if (!std::isfinite(value)) throw Invalid(source, "contains a non-finite number (NaN or Inf)");
    }
  }

  const bool has_normals = !attrib.normals.empty();
  TriangleMesh mesh;
  std::map<std::tuple<int, int, int>, uint32_t> vertex_of;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    for (const tinyobj::index_t& index : shape.mesh.indices) {
      if (index.texcoord_index < 0) {
        throw Invalid(source, "a face of '" + shape.name + "' has a vertex without a texture coordinate");
      }
      if (has_normals && index.normal_index < 0) {
        throw Invalid(source, "a face of '" + shape.name + "' has a vertex without a normal");
      }
      const auto key = std::make_tuple(index.vertex_index, index.texcoord_index, index.normal_index);
      auto [it, inserted] = vertex_of.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
      if (inserted) {
        const size_t p = 3 * static_cast<size_t>(index.vertex_index);
        const size_t t = 2 * static_cast<size_t>(index.texcoord_index);
        mesh.positions.emplace_back(attrib.vertices[p], attrib.vertices[p + 1], attrib.vertices[p + 2]);
        mesh.uvs.emplace_back(attrib.texcoords[t], attrib.texcoords[t + 1]);
        if (has_normals) {
          const size_t n = 3 * static_cast<size_t>(index.normal_index);
          mesh.normals.emplace_back(attrib.normals[n], attrib.normals[n + 1], attrib.normals[n + 2]);
        }
      }
      mesh.indices.push_back(it->second);
    }
  }
  return mesh;
}

}  // namespace loom
