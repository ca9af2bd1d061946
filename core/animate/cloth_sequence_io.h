#pragma once
// A ClothAnimation as files other tools open: an OBJ of the cloth per frame, and
// one glTF 2.0 binary (.glb) holding the cloth's mesh with a morph target per
// frame after the first and an animation whose weights blend them in turn
// (linearly between frames), which Blender imports as shape keys played over
// time, and the balls as meshes moved by translation animations
// (core/scene/gltf_loader.h reads each back).

#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "core/animate/animation.h"
#include "core/scene/gltf_loader.h"

namespace loom::animate {

// The animation's cloth as a sequence: its triangles (KnitCloth::Triangles), uv
// (i / (loops − 1), j / (courses − 1)), frame k at k / rate seconds.
MeshSequence ClothSequence(const ClothAnimation& animation);

// A solid moved rigidly through a sequence: its mesh where it starts, and its
// displacement from there at each frame.
struct RigidTrack {
  std::string name;
  TriangleMesh mesh;
  std::vector<glm::vec3> displacements;
};

// The animation's sphere colliders as meshes named "collider_K" (K the
// collider's index in the spec) with their motions; planes and boxes are left
// to the scene.
std::vector<RigidTrack> SolidTracks(const ClothAnimation& animation);

// frame_00000.obj, frame_00001.obj, … in `directory` (created), each written
// atomically.
void WriteObjSequence(const MeshSequence& sequence, const std::filesystem::path& directory);

// The sequence as the file's first mesh ("cloth"), then the solids, each
// displacement at the sequence's frame times. .glb (binary) unless the name ends
// in .gltf (JSON, buffer embedded); written atomically.
void WriteGltfSequence(const MeshSequence& sequence, const std::filesystem::path& path,
                       const std::vector<RigidTrack>& solids = {});

}  // namespace loom::animate
