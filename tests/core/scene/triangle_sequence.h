#pragma once
// A glTF sequence small enough to check by hand, for the scene tests: one
// triangle over two frames (the cloth, raised by 1 at frame 1) and a second mesh
// "ball", the same triangle raised by 2 at frame 1.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/animate/cloth_sequence_io.h"
#include "core/scene/gltf_loader.h"
#include "core/util/file_io.h"

namespace loom::scene_test {

inline MeshSequence TriangleSequence() {
  MeshSequence sequence;
  sequence.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  sequence.mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  sequence.mesh.indices = {0, 1, 2};
  sequence.frames = {sequence.mesh.positions, {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}};
  sequence.times = {0.0f, 0.04f};
  return sequence;
}

// The sequence with its ball as .glb bytes (written through a file named `stem`
// in the test's temporary directory).
inline std::string TriangleSequenceGlb(const std::string& stem) {
  const MeshSequence sequence = TriangleSequence();
  const auto path = std::filesystem::path(::testing::TempDir()) / (stem + ".glb");
  animate::WriteGltfSequence(sequence, path, {{"ball", sequence.mesh, {glm::vec3(0), glm::vec3(0, 0, 2)}}});
  return ReadFile(path);
}

}  // namespace loom::scene_test
