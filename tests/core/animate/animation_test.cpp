#include "core/animate/animation.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/animate/cloth_sequence_io.h"
#include "core/scene/obj_loader.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::animate {
namespace {

// An empty directory of this test's own.
std::filesystem::path ScratchDir(const std::string& name) {
  const auto dir =
      std::filesystem::path(::testing::TempDir()) / ("loom_animation_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A 4 × 6 cloth hung by its top course, a sphere passing beneath it, 0.4 s at
// 25 frames a second.
v1::AnimationSpec Hanging() {
  return ParseSpecJson<v1::AnimationSpec>(R"({
    "cloth": {"loops": 4, "courses": 6, "wale_axis": {"z": -1}},
    "pins": [{"course": 0}],
    "colliders": [{"sphere": {"centre": {"x": 1.5, "y": -3, "z": -3}, "radius": 1},
                   "motion": [{"velocity": {"y": 5}, "end_seconds": 0.4}]}],
    "duration_seconds": 0.4
  })",
                                          "animation");
}

TEST(RunAnimation, RecordsEveryFrameOfTheSpec) {
  size_t reported = 0;
  const ClothAnimation animation = RunAnimation(Hanging(), [&](size_t done, size_t total) {
    EXPECT_EQ(total, 10u);
    reported = done;
  });
  EXPECT_EQ(reported, 10u);
  ASSERT_EQ(animation.frames.size(), 11u);
  EXPECT_EQ(animation.frames_per_second, 25.0f);
  // The top course holds; the rest falls, away from the start.
  EXPECT_EQ(animation.frames.back()[2], animation.frames[0][2]);
  EXPECT_LT(animation.frames.back()[20].z, animation.frames[0][20].z - 0.1f);
  EXPECT_GT(animation.counts.steps, 10);
  EXPECT_GE(animation.min_collider_distance, 0.0f);
}

TEST(RunAnimation, RefusesABadSpecNamingTheField) {
  v1::AnimationSpec spec = Hanging();
  spec.mutable_cloth()->set_loops(0);
  try {
    RunAnimation(spec);
    FAIL() << "a cloth of no loops ran";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find("animation.cloth.loops: 0 is below 2"), std::string::npos) << error.what();
  }
}

TEST(RunAnimation, TheSpecSetsTheModelsConstants) {
  // Unset, the defaults; each one set replaces its default alone.
  const KnitMechanics defaults;
  const v1::AnimationSpec spec = ParseSpecJson<v1::AnimationSpec>(
      R"({"mechanics": {"contact_damping": 0, "courant": 0.25, "self_collision": false}})", "animation");
  const KnitMechanics set = Mechanics(spec.mechanics());
  EXPECT_EQ(set.contact_damping, 0.0f);
  EXPECT_EQ(set.courant, 0.25f);
  EXPECT_FALSE(set.self_collision);
  EXPECT_EQ(set.static_friction, defaults.static_friction);
  EXPECT_EQ(set.air_viscosity, defaults.air_viscosity);
  EXPECT_EQ(Mechanics({}).contact_damping, defaults.contact_damping);
  EXPECT_TRUE(Mechanics({}).self_collision);
  // They reach the simulation: without air the hanging cloth falls faster, and
  // half the courant number takes more steps.
  v1::AnimationSpec still_air = Hanging();
  still_air.mutable_mechanics()->set_air_viscosity(0.0f);
  v1::AnimationSpec fine = Hanging();
  fine.mutable_mechanics()->set_courant(0.25f);
  const ClothAnimation base = RunAnimation(Hanging()), airless = RunAnimation(still_air), finer = RunAnimation(fine);
  EXPECT_LT(airless.frames.back()[20].z, base.frames.back()[20].z - 1e-3f);
  EXPECT_GT(finer.counts.steps, base.counts.steps * 3 / 2);
}

TEST(ClothSequence, GltfRoundTripKeepsEveryFrame) {
  const ClothAnimation animation = RunAnimation(Hanging());
  const auto dir = ScratchDir("gltf");
  const auto path = dir / "cloth.glb";
  WriteGltfSequence(ClothSequence(animation), path);
  const MeshSequence read = ReadGltfSequence(path);
  ASSERT_EQ(read.frames.size(), animation.frames.size());
  ASSERT_EQ(read.times.size(), animation.frames.size());
  EXPECT_FLOAT_EQ(read.times[5], 0.2f);
  EXPECT_EQ(read.mesh.indices.size(), 3 * 2 * 3 * 5u);
  EXPECT_EQ(read.mesh.uvs.size(), 24u);
  for (size_t k = 0; k < read.frames.size(); ++k) {
    for (size_t v = 0; v < 24; ++v) {
      // Frame k is frame 0 plus target k − 1's offset: exact to float rounding.
      EXPECT_NEAR(glm::distance(read.frames[k][v], animation.frames[k][v]), 0.0f, 1e-5f) << k << " " << v;
    }
  }
  // A .gltf (JSON, buffer embedded) reads back alike.
  WriteGltfSequence(ClothSequence(animation), dir / "cloth.gltf");
  EXPECT_EQ(ReadGltfSequence(dir / "cloth.gltf").frames.back(), read.frames.back());
}

// A 6 × 6 patch on a floor, and a ball carried along +x at 5 loops/s for 0.1 s
// above it, then let go; 0.4 s.
v1::AnimationSpec BallOverPatch() {
  return ParseSpecJson<v1::AnimationSpec>(R"({
    "cloth": {"loops": 6, "courses": 6, "origin": {"x": -2.5, "y": -2.5, "z": 0.6}},
    "colliders": [{"plane": {"point": {}, "normal": {"z": 1}}},
                  {"sphere": {"centre": {"z": 4}, "radius": 1.5, "mass": 10, "release_seconds": 0.1},
                   "motion": [{"velocity": {"x": 5}, "end_seconds": 0.2}]}],
    "duration_seconds": 0.4
  })",
                                          "animation");
}

TEST(ClothSequence, BallsMoveInTheGltfAsTheyMovedInTheSimulation) {
  const ClothAnimation animation = RunAnimation(BallOverPatch());
  ASSERT_EQ(animation.collider_tracks.size(), 2u);
  const std::vector<glm::vec3>& ball = animation.collider_tracks[1];
  ASSERT_EQ(ball.size(), 11u);
  // Carried until 0.1 s, then falling freely from there at 5 loops/s along x.
  EXPECT_NEAR(ball[2].x, 0.4f, 1e-5f);
  EXPECT_NEAR(ball[2].z, 0.0f, 1e-6f);
  EXPECT_NEAR(ball[10].x, 2.0f, 1e-3f);
  EXPECT_NEAR(ball[10].z, -0.5f * 9.81f * 0.09f, 1e-3f);
  EXPECT_EQ(animation.collider_tracks[0].back(), glm::vec3(0.0f));

  const auto path = ScratchDir("ball") / "ball.glb";
  WriteGltfSequence(ClothSequence(animation), path, SolidTracks(animation));
  // The first mesh is still the cloth…
  EXPECT_EQ(ReadGltfSequence(path).frames.back(), ReadGltfSequence(path, "cloth").frames.back());
  EXPECT_EQ(ReadGltfSequence(path).mesh.positions.size(), 36u);
  // …and the ball's mesh is a sphere of its radius about where it was at each frame.
  const MeshSequence read = ReadGltfSequence(path, "collider_1");
  ASSERT_EQ(read.frames.size(), 11u);
  for (const size_t k : {0u, 2u, 10u}) {
    Bounds bounds;
    bounds.Add(read.frames[k]);
    EXPECT_NEAR(glm::distance(bounds.centre(), glm::vec3(0, 0, 4) + ball[k]), 0.0f, 1e-4f) << k;
    EXPECT_NEAR(bounds.high.z - bounds.low.z, 3.0f, 1e-4f);
  }
  EXPECT_EQ(ParseGltfFrame(ReadFile(path), 10, "upload", "collider_1").positions, read.frames[10]);
  // The floor has no mesh; asking for it names what there is.
  try {
    ReadGltfSequence(path, "collider_0");
    FAIL() << "a plane's mesh was read";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("no mesh named 'collider_0' (it has 'cloth', 'collider_1')"),
              std::string::npos)
        << error.what();
  }
}

// A 6 × 6 patch dropped onto a collider of radius 3 centred 4 below it, for 1 s.
v1::AnimationSpec DropOnto(const std::string& collider) {
  return ParseSpecJson<v1::AnimationSpec>(R"({
    "cloth": {"loops": 6, "courses": 6, "origin": {"x": -2.5, "y": -2.5, "z": 0}},
    "colliders": [)" + collider + R"(],
    "duration_seconds": 1
  })",
                                          "animation");
}

TEST(RunAnimation, AMeshColliderActsAsTheSolidItBounds) {
  const ClothAnimation on_sphere = RunAnimation(DropOnto(R"({"sphere": {"centre": {"z": -4}, "radius": 3}})"));
  // The built-in sphere, 64 × 32 segments, placed by its transform…
  const ClothAnimation on_mesh = RunAnimation(DropOnto(R"({"mesh": {"mesh": {"builtin": "BUILTIN_SHAPE_SPHERE",
      "segments": 32}, "transform": {"translation": {"z": -4}, "scale": {"x": 3, "y": 3, "z": 3}}}})"));
  // …holds the cloth where the sphere does, within its facets' error (0.015).
  for (size_t p = 0; p < 36; ++p) {
    EXPECT_NEAR(glm::distance(on_mesh.frames.back()[p], on_sphere.frames.back()[p]), 0.0f, 0.05f) << p;
  }
  EXPECT_LT(on_sphere.frames.back()[14].z, -0.1f);  // it fell onto the ball
  EXPECT_GE(on_mesh.min_collider_distance, 0.0f);

  // An OBJ beside the spec, read by the resolver; without one it cannot be read.
  const auto dir = ScratchDir("mesh_collider");
  {
    std::ofstream obj(dir / "tetrahedron.obj");
    obj << "v 0 0 -1\nv 1 0 -2\nv 0 1 -2\nv 0 0 -2\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
  }
  const v1::AnimationSpec file = DropOnto(R"({"mesh": {"mesh": {"obj_path": "tetrahedron.obj"}}})");
  EXPECT_EQ(RunAnimation(file, {}, 0, FileMeshResolver(dir)).colliders.size(), 1u);
  try {
    RunAnimation(file);
    FAIL() << "a mesh file was read without a resolver";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("animation.colliders[0].mesh: mesh files cannot be read here"),
              std::string::npos)
        << error.what();
  }
}

TEST(ClothSequence, RefusesBrokenGltfNamingTheFile) {
  const auto path = ScratchDir("broken") / "broken.glb";
  {
    std::ofstream out(path, std::ios::binary);
    out << std::string("glTF\x02\0\0\0 not really", 18);
  }
  try {
    ReadGltfSequence(path);
    FAIL() << "a broken file was read";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find("broken.glb"), std::string::npos) << error.what();
  }
}

// One triangle whose positions and indices lie in "triangle.bin" beside the file.
constexpr const char* kExternalBufferGltf = R"({
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "triangle.bin", "byteLength": 48}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}]
})";

TEST(ClothSequence, UploadedBytesReadAsTheFileButOpenNoOtherFile) {
  const ClothAnimation animation = RunAnimation(Hanging());
  const auto dir = ScratchDir("bytes");
  WriteGltfSequence(ClothSequence(animation), dir / "cloth.glb");
  const MeshSequence bytes = ParseGltfSequence(ReadFile(dir / "cloth.glb"), "upload 1");
  const MeshSequence file = ReadGltfSequence(dir / "cloth.glb");
  EXPECT_EQ(bytes.frames, file.frames);
  EXPECT_EQ(bytes.mesh.indices, file.mesh.indices);

  // A .gltf naming a buffer file reads from its own directory, but as uploaded
  // bytes it is refused: a server never opens a path a client names.
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t indices[3] = {0, 1, 2};
  std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  WriteFileAtomic(dir / "triangle.bin", bin);
  WriteFileAtomic(dir / "triangle.gltf", kExternalBufferGltf);
  EXPECT_EQ(ReadGltfSequence(dir / "triangle.gltf").mesh.positions[1], glm::vec3(1, 0, 0));
  // Run from that directory, where opening "triangle.bin" would succeed.
  const auto cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  try {
    ParseGltfSequence(kExternalBufferGltf, "upload 2");
    ADD_FAILURE() << "an uploaded glTF read a file";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find("upload 2"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("the file 'triangle.bin'"), std::string::npos) << error.what();
  }
  std::filesystem::current_path(cwd);
}

TEST(ClothSequence, ObjFramesHoldTheClothAtEachFrame) {
  const ClothAnimation animation = RunAnimation(Hanging());
  const auto dir = ScratchDir("obj");
  WriteObjSequence(ClothSequence(animation), dir / "frames");
  const TriangleMesh last = ParseObj(ReadFile(dir / "frames" / "frame_00010.obj"), "frame 10");
  ASSERT_EQ(last.positions.size(), 24u);
  EXPECT_EQ(last.triangle_count(), 30u);
  EXPECT_NEAR(glm::distance(last.positions[20], animation.frames[10][20]), 0.0f, 1e-5f);
  EXPECT_FALSE(std::filesystem::exists(dir / "frames" / "frame_00011.obj"));
}

}  // namespace
}  // namespace loom::animate
