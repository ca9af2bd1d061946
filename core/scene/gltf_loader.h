#pragma once
// glTF 2.0 meshes, and mesh sequences: a mesh's first primitive (triangles,
// positions, texture coordinates), and the frames its morph targets make when a
// weights animation plays them one at a time, moved by its node's translation
// animation if it has one — what Loom's animation jobs write (the cloth, and the
// balls that move with it; core/animate/cloth_sequence_io.h) and Blender exports
// from shape keys and object motion. A mesh without such animations is a
// sequence of one frame. The mesh is the one of the name asked for, or the
// file's first.

#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "core/scene/triangle_mesh.h"

namespace loom {

struct MeshSequence {
  TriangleMesh mesh;                           // frame 0: positions, uvs if present, indices
  std::vector<std::vector<glm::vec3>> frames;  // every frame's positions, frame 0 included
  std::vector<float> times;                    // seconds, one a frame
};

// Reads a .glb or .gltf file; a .gltf's external buffers are read from beside it.
// Error(kInvalidArgument) naming the file and the part for anything else (no
// triangles, other accessor types, out-of-range indices, past the mesh caps of
// core/spec/limits.h).
MeshSequence ReadGltfSequence(const std::filesystem::path& path, const std::string& mesh_name = {});
// The same for bytes that came from elsewhere (an upload; errors name `name`):
// they may open no file, so their buffers must be inside (a .glb, or data: URIs).
// Images are not decoded.
MeshSequence ParseGltfSequence(const std::string& bytes, const std::string& name, const std::string& mesh_name = {});

// Frame `frame` of the sequence in uploaded `bytes`, made alone (a sequence of
// thousands of frames is never held whole): as SequenceFrame of
// ParseGltfSequence, in the memory of the bytes twice and one frame.
TriangleMesh ParseGltfFrame(const std::string& bytes, size_t frame, const std::string& name,
                           const std::string& mesh_name = {});

// Frame `frame` of the sequence: its positions with frame 0's uvs and triangles,
// not yet prepared (core/scene/mesh_preparation.h). Error(kInvalidArgument)
// naming `name` when there is no such frame.
TriangleMesh SequenceFrame(const MeshSequence& sequence, size_t frame, const std::string& name);

// Whether mesh file bytes beginning with `head` are glTF (binary "glTF", or JSON
// "{" after white space) rather than OBJ.
bool LooksLikeGltf(std::string_view head);

}  // namespace loom
