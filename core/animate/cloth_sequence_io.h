#pragma once
// A ClothAnimation as files other tools open: an OBJ per frame, and one glTF 2.0
// binary (.glb) holding the cloth's mesh with a morph target per frame after the
// first and an animation whose weights blend them in turn (linearly between
// frames), which Blender imports as shape keys played over time. The glTF reader
// reads such a sequence back, and a plain glTF mesh as a sequence of one frame.

#include <filesystem>
#include <glm/glm.hpp>
#include <vector>

#include "core/animate/animation.h"
#include "core/scene/triangle_mesh.h"

namespace loom::animate {

// The cloth's triangle mesh at `positions`: its triangles (KnitCloth::Triangles),
// uv (i / (loops − 1), j / (courses − 1)) and area-weighted normals.
TriangleMesh ClothMesh(const KnitCloth& cloth, const std::vector<glm::vec3>& positions);

// frame_00000.obj, frame_00001.obj, … in `directory` (created), each written
// atomically.
void WriteObjSequence(const ClothAnimation& animation, const std::filesystem::path& directory);

// Written atomically.
void WriteGltfSequence(const ClothAnimation& animation, const std::filesystem::path& path);

struct MeshSequence {
  TriangleMesh mesh;                           // frame 0: positions, uvs if present, indices
  std::vector<std::vector<glm::vec3>> frames;  // every frame's positions, frame 0 included
  std::vector<float> times;                    // seconds, one a frame
};

// Reads the first mesh of a .glb or .gltf file: its first primitive's
// triangles, and the frames its morph targets make when a weights animation
// plays them one at a time. Error(kInvalidArgument) naming the file and the part
// for anything else (no triangles, other accessor types, out-of-range indices).
MeshSequence ReadGltfSequence(const std::filesystem::path& path);

}  // namespace loom::animate
