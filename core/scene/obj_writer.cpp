#include "core/scene/obj_writer.h"

#include <charconv>
#include <string>

#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

// Shortest round-trip text for a float, independent of the C locale.
void Append(std::string& out, float value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.push_back(' ');
  out.append(buffer, result.ptr);
}

void Append(std::string& out, uint64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

}  // namespace

void WriteObj(const TriangleMesh& mesh, const std::filesystem::path& path, int tiles_x, int tiles_y) {
  if (tiles_x < 1 || tiles_y < 1) {
    throw Error(ErrorCode::kInvalidArgument, "OBJ tile counts must be at least 1, got " + std::to_string(tiles_x) +
                                                 " x " + std::to_string(tiles_y));
  }
  const size_t vertices = mesh.positions.size();
  const bool has_uvs = mesh.uvs.size() == vertices, has_normals = mesh.normals.size() == vertices;
  std::string out = "# Loom mesh, " + std::to_string(tiles_x) + " x " + std::to_string(tiles_y) + " tiles\n";
  for (int j = 0; j < tiles_y; ++j) {
    for (int i = 0; i < tiles_x; ++i) {
      for (const glm::vec3& p : mesh.positions) {
        out += 'v';
        Append(out, p.x + static_cast<float>(i));
        Append(out, p.y + static_cast<float>(j));
        Append(out, p.z);
        out += '\n';
      }
    }
  }
  if (has_uvs) {
    for (const glm::vec2& uv : mesh.uvs) {
      out += "vt";
      Append(out, uv.x);
      Append(out, uv.y);
      out += '\n';
    }
  }
  if (has_normals) {
    for (const glm::vec3& n : mesh.normals) {
      out += "vn";
      Append(out, n.x);
      Append(out, n.y);
      Append(out, n.z);
      out += '\n';
    }
  }
  for (uint64_t copy = 0; copy < static_cast<uint64_t>(tiles_x) * static_cast<uint64_t>(tiles_y); ++copy) {
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      out += 'f';
      for (size_t k = 0; k < 3; ++k) {
        const uint64_t index = mesh.indices[t + k] + 1;  // OBJ is 1-based
        out += ' ';
        Append(out, copy * vertices + index);
        if (has_uvs || has_normals) out += '/';
        if (has_uvs) Append(out, index);
        if (has_normals) {
          out += '/';
          Append(out, index);
        }
      }
      out += '\n';
    }
  }
  WriteFileAtomic(path, out);
}

}  // namespace loom
