#pragma once
// Wavefront OBJ meshes for scenes. The text form is what travels: the server
// receives a mesh as uploaded bytes and never opens a client path (DESIGN.md
// "Security"), loom-lab reads a file and passes its text.
//
// The text may arrive in pieces of any size (ObjParser::Feed), so that a large
// upload is parsed while it streams from disk instead of held whole in memory.
// Every index and count is checked as it is read: a face that refers to a vertex,
// texture coordinate or normal not defined before it (positive, or negative
// counting back from the last one defined, as OBJ defines them; 0 is no index) is
// an error naming its line, and the caps of MeshLimits end the parse at the line
// that passes them, so memory never grows past what the caps allow
// (docs/operations.md "Limits").
//
// Read: v (x y z, optional w or vertex colour ignored), vt (u [v [w]]), vn, and
// f with v, v/vt, v//vn or v/vt/vn corners; a quad is split along its shorter
// diagonal, a larger polygon fanned from its first corner. Ignored: comments,
// o, g, s, usemtl, mtllib, l, p and every other statement.
//
// The result is ready for PrepareMesh (core/scene/mesh_preparation.h): one vertex
// per distinct (position, uv, normal) triple, normals empty when the file has none.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "core/scene/triangle_mesh.h"

namespace loom {

// What one parse may build. The defaults are the caps of core/spec/limits.h; a
// scene passes what its earlier meshes left of them.
struct MeshLimits {
  int64_t triangles;
  // Each list: positions, texture coordinates, normals, and the distinct vertices built.
  int64_t vertices;

  MeshLimits();
};

class ObjParser {
 public:
  // `source` names the mesh in errors ("cloth.obj", "scene.objects[2] (cloth)").
  explicit ObjParser(std::string source, MeshLimits limits = {});
  ~ObjParser();
  ObjParser(const ObjParser&) = delete;
  ObjParser& operator=(const ObjParser&) = delete;

  // The next bytes of the text. Errors are Error(kInvalidArgument) naming the
  // source, the line and the problem: a malformed statement, an index out of range,
  // a non-finite number, a face without texture coordinates (a fabric is tiled
  // through the UVs) or a cap exceeded.
  void Feed(std::string_view bytes);
  // After the last piece; also an error when the mesh has no faces. Call once.
  TriangleMesh Finish();

 private:
  struct State;
  void ParseLine(std::string_view line);
  std::unique_ptr<State> state_;
};

// The whole text at once.
TriangleMesh ParseObj(std::string_view text, const std::string& source, MeshLimits limits = {});

}  // namespace loom
