#pragma once
// A ClothAnimation as files other tools open: an OBJ per frame, and one glTF 2.0
// binary (.glb) holding the cloth's mesh with a morph target per frame after the
// first and an animation whose weights blend them in turn (linearly between
// frames), which Blender imports as shape keys played over time
// (core/scene/gltf_loader.h reads it back).

#include <filesystem>
#include <glm/glm.hpp>
#include <vector>

#include "core/animate/animation.h"
#include "core/scene/gltf_loader.h"

namespace loom::animate {

// The animation's cloth as a sequence: its triangles (KnitCloth::Triangles), uv
// (i / (loops − 1), j / (courses − 1)), frame k at k / rate seconds.
MeshSequence ClothSequence(const ClothAnimation& animation);

// frame_00000.obj, frame_00001.obj, … in `directory` (created), each written
// atomically.
void WriteObjSequence(const MeshSequence& sequence, const std::filesystem::path& directory);

// .glb (binary) unless the name ends in .gltf (JSON, buffer embedded); written
// atomically.
void WriteGltfSequence(const MeshSequence& sequence, const std::filesystem::path& path);

}  // namespace loom::animate
