#include "core/scene/mesh_sequence_cache.h"

#include <gtest/gtest.h>

#include "core/scene/scene_geometry.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "tests/core/scene/triangle_sequence.h"

namespace loom {
namespace {

// A scene of frame `frame` of mesh `mesh` of artifact "a1" (or of a file).
v1::SceneSpec FrameOf(int frame, const std::string& mesh = "", bool file = false) {
  const std::string source = file ? R"("gltf_path": "cloth.glb")" : R"("artifact": "a1")";
  return WithDefaults(ParseSpecJson<v1::SceneSpec>(
      R"({"objects": [{"mesh": {)" + source + R"(, "frame": )" + std::to_string(frame) + R"(, "gltf_mesh": ")" +
          mesh + R"("}}], "camera": {"position": {"x": 0, "y": -3, "z": 1}}})",
      "scene"));
}

TEST(MeshSequenceCache, AnArtifactsSequenceIsReadOnceForAllItsFrames) {
  const std::string glb = scene_test::TriangleSequenceGlb("mesh_sequence_cache_test");
  int reads = 0;
  const MeshTextResolver bytes = [&](const v1::MeshRef&, const TextSink& consume) {
    ++reads;
    consume(glb);
  };
  MeshSequenceCache sequences;
  for (const int frame : {1, 0, 1}) {
    const std::vector<SceneMesh> kept = BuildSceneGeometry(FrameOf(frame), bytes, &sequences);
    const std::vector<SceneMesh> read = BuildSceneGeometry(FrameOf(frame), bytes);
    EXPECT_EQ(kept[0].mesh.positions, read[0].mesh.positions);
    EXPECT_EQ(kept[0].mesh.normals, read[0].mesh.normals);
    EXPECT_EQ(kept[0].mesh.uvs, read[0].mesh.uvs);
    EXPECT_EQ(kept[0].mesh.indices, read[0].mesh.indices);
  }
  EXPECT_EQ(BuildSceneGeometry(FrameOf(1), bytes, &sequences)[0].mesh.positions[1], glm::vec3(1, 0, 1));
  EXPECT_EQ(reads, 1 + 3);  // once into the cache, and each build without it
  // Another mesh of the file is a sequence of its own.
  EXPECT_EQ(BuildSceneGeometry(FrameOf(1, "ball"), bytes, &sequences)[0].mesh.positions[1], glm::vec3(1, 0, 2));
  EXPECT_EQ(reads, 5);
  // A frame the sequence lacks is refused as when it is read.
  try {
    BuildSceneGeometry(FrameOf(2), bytes, &sequences);
    FAIL() << "frame 2 of 2 was taken";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "mesh scene.objects[0]: frame 2 of a sequence of 2 frame(s)");
  }
  EXPECT_EQ(reads, 5);
  // Files may change under their names: they are read every time.
  MeshSequenceCache files;
  BuildSceneGeometry(FrameOf(0, "", true), bytes, &files);
  BuildSceneGeometry(FrameOf(1, "", true), bytes, &files);
  EXPECT_EQ(reads, 7);
  EXPECT_EQ(files.bytes(), 0u);
}

TEST(MeshSequenceCache, KeepsWithinItsBudgetDroppingTheLeastRecentlyUsed) {
  const auto triangle = std::make_shared<const MeshSequence>(scene_test::TriangleSequence());
  const size_t size = 3 * sizeof(glm::vec2) + 3 * sizeof(uint32_t) + 2 * 3 * sizeof(glm::vec3);
  MeshSequenceCache cache(2 * size + size / 2);  // two fit, three do not
  cache.Keep("a", "", triangle);
  cache.Keep("b", "", triangle);
  EXPECT_EQ(cache.Find("a", ""), triangle);  // now a is the more recent
  cache.Keep("c", "", triangle);
  EXPECT_EQ(cache.Find("a", ""), triangle);
  EXPECT_EQ(cache.Find("b", ""), nullptr);
  EXPECT_EQ(cache.Find("c", ""), triangle);
  EXPECT_EQ(cache.Find("c", "ball"), nullptr);
  EXPECT_EQ(cache.bytes(), 2 * size);
  cache.Keep("c", "", triangle);  // kept again: still once
  EXPECT_EQ(cache.bytes(), 2 * size);
  // A sequence larger than the whole budget is not kept.
  MeshSequenceCache small(size - 1);
  small.Keep("a", "", triangle);
  EXPECT_EQ(small.Find("a", ""), nullptr);
  EXPECT_EQ(small.bytes(), 0u);
}

}  // namespace
}  // namespace loom
