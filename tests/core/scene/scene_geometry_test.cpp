#include "core/scene/scene_geometry.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "core/scene/camera.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "tests/core/scene/triangle_sequence.h"

namespace loom {
namespace {

v1::SceneSpec Scene(const char* json) { return WithDefaults(ParseSpecJson<v1::SceneSpec>(json, "scene")); }

TEST(SceneGeometry, TransformsBuiltinMeshesIntoWorldSpace) {
  const auto scene = Scene(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE", "segments": 2},
      "transform": {"translation": {"x": 1, "y": 0, "z": 2}, "rotation_degrees": {"x": 90},
                    "scale": {"x": 4, "y": 2, "z": 1}}}],
      "camera": {"position": {"x": 0, "y": -3, "z": 1}}})");
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver("."));
  ASSERT_EQ(meshes.size(), 1u);
  const TriangleMesh& mesh = meshes[0].mesh;
  // The plane's +z normal, rotated 90° about x, points along -y.
  EXPECT_NEAR(glm::distance(mesh.normals[0], glm::vec3(0, -1, 0)), 0.0f, 1e-5f);
  // Its corner (-0.5, -0.5, 0) scales to (-2, -1, 0), rotates to (-2, 0, -1), moves to (-1, 0, 1).
  EXPECT_NEAR(glm::distance(mesh.positions[0], glm::vec3(-1, 0, 1)), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::distance(glm::vec3(mesh.tangents[0]), glm::vec3(1, 0, 0)), 0.0f, 1e-5f);
}

TEST(SceneGeometry, ArtifactsAreNotReadFromFiles) {
  const auto scene = Scene(R"({"objects": [{"mesh": {"artifact":
      "0000000000000000000000000000000000000000000000000000000000000000"}}],
      "camera": {"position": {"x": 0, "y": -3, "z": 1}}})");
  EXPECT_THROW(BuildSceneGeometry(scene, FileMeshResolver(".")), Error);
}

MeshTextResolver Text(std::string obj) {
  return [obj](const v1::MeshRef&, const TextSink& consume) { consume(obj); };
}

constexpr const char* kUvlessTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST(SceneGeometry, ObjErrorsNameTheObject) {
  const auto scene = Scene(R"({"objects": [{"name": "cloth", "mesh": {"obj_path": "flat.obj"},
      "fabric": {"fabric": {"knit": {}}}}], "camera": {"position": {"x": 0, "y": -3, "z": 1}}})");
  try {
    BuildSceneGeometry(scene, Text(kUvlessTriangle));
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              "mesh scene.objects[0] (cloth): has no texture coordinates (vt): a fabric is tiled over the mesh "
              "through its UVs");
  }
}

TEST(SceneGeometry, PlainObjectsNeedNoUvs) {
  const auto scene = Scene(R"({"objects": [{"name": "table", "mesh": {"obj_path": "table.obj"}}],
      "camera": {"position": {"x": 0, "y": -3, "z": 1}}})");
  const auto meshes = BuildSceneGeometry(scene, Text(kUvlessTriangle));
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].mesh.uvs.size(), 3u);
  EXPECT_EQ(meshes[0].mesh.tangents.size(), 3u);
  EXPECT_EQ(meshes[0].report.zero_area_uv_triangles, 0u);
}

// The resolver's bytes in pieces of one byte each.
MeshTextResolver Bytewise(std::string bytes) {
  return [bytes](const v1::MeshRef&, const TextSink& consume) {
    for (const char& c : bytes) consume(std::string_view(&c, 1));
  };
}

TEST(SceneGeometry, GltfSequenceFramesAndObjsAreToldApartWhateverThePieces) {
  const std::string glb = scene_test::TriangleSequenceGlb("scene_geometry_test_sequence");

  const char* const json = R"({"objects": [{"mesh": {"gltf_path": "cloth.glb", "frame": %d}}],
      "camera": {"position": {"x": 0, "y": -3, "z": 1}}})";
  char spec[256];
  std::snprintf(spec, sizeof spec, json, 1);
  const auto frame1 = BuildSceneGeometry(Scene(spec), Bytewise(glb));
  ASSERT_EQ(frame1[0].mesh.positions.size(), 3u);
  EXPECT_EQ(frame1[0].mesh.positions[1], glm::vec3(1, 0, 1));
  std::snprintf(spec, sizeof spec, json, 0);
  EXPECT_EQ(BuildSceneGeometry(Scene(spec), Bytewise(glb))[0].mesh.positions[1], glm::vec3(1, 0, 0));
  std::snprintf(spec, sizeof spec, json, 2);
  try {
    BuildSceneGeometry(Scene(spec), Bytewise(glb));
    FAIL() << "frame 2 of 2 was read";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "mesh scene.objects[0]: frame 2 of a sequence of 2 frame(s)");
  }
  // The mesh asked for by name, at the frame asked for.
  const auto named = [&](const char* mesh) {
    return Scene((R"({"objects": [{"mesh": {"gltf_path": "cloth.glb", "frame": 1, "gltf_mesh": ")" + std::string(mesh) +
                  R"("}}], "camera": {"position": {"x": 0, "y": -3, "z": 1}}})")
                     .c_str());
  };
  EXPECT_EQ(BuildSceneGeometry(named("ball"), Bytewise(glb))[0].mesh.positions[1], glm::vec3(1, 0, 2));
  EXPECT_EQ(BuildSceneGeometry(named("cloth"), Bytewise(glb))[0].mesh.positions[1], glm::vec3(1, 0, 1));
  try {
    BuildSceneGeometry(named("lamp"), Bytewise(glb));
    FAIL() << "a mesh the file does not have was read";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("no mesh named 'lamp' (it has 'cloth', 'ball')"), std::string::npos)
        << error.what();
  }
  // An OBJ shorter than the bytes that tell the formats apart, a byte at a time.
  const auto obj = BuildSceneGeometry(Scene(R"({"objects": [{"mesh": {"obj_path": "t.obj"}}],
      "camera": {"position": {"x": 0, "y": -3, "z": 1}}})"),
                                      Bytewise(kUvlessTriangle));
  EXPECT_EQ(obj[0].mesh.triangle_count(), 1u);
}

// The caps hold for the scene's objects together: repeating one mesh does not
// multiply what a scene may build.
TEST(SceneGeometry, TheCapsHoldForTheWholeScene) {
  std::string objects;
  for (int i = 0; i < 64; ++i) objects += std::string(i ? "," : "") + R"({"mesh": {"obj_path": "big.obj"}})";
  const auto scene =
      Scene((R"({"objects": [)" + objects + R"(], "camera": {"position": {"x": 0, "y": -3, "z": 1}}})").c_str());
  // A strip of 100k triangles on 100 002 vertices: the 40th copy passes the
  // vertex cap (4M − 39 × 100 002 = 99 922 left).
  std::string strip = "v 0 0 0\nv 0 1 0\n";
  for (int i = 1; i <= 50'000; ++i) strip += "v " + std::to_string(i) + " 0 0\nv " + std::to_string(i) + " 1 0\n";
  for (int i = 0; i < 50'000; ++i) {
    const int a = 2 * i + 1;
    strip += "f " + std::to_string(a) + " " + std::to_string(a + 2) + " " + std::to_string(a + 1) + "\nf " +
             std::to_string(a + 1) + " " + std::to_string(a + 2) + " " + std::to_string(a + 3) + "\n";
  }
  try {
    BuildSceneGeometry(scene, Text(strip));
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "mesh scene.objects[39]: line 99923: more than 99922 positions (v)");
  }
}

TEST(Camera, PerspectiveProjectsTheTargetToTheImageCentre) {
  const auto scene = Scene(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}}],
      "camera": {"position": {"x": 1, "y": -3, "z": 2}, "target": {"x": 0.5, "y": 0.2, "z": 0.1}}})");
  const CameraMatrices camera = MakeCameraMatrices(scene.camera(), 16.0f / 9.0f);
  const glm::vec4 clip = camera.projection * camera.view * glm::vec4(0.5f, 0.2f, 0.1f, 1.0f);
  EXPECT_NEAR(clip.x / clip.w, 0.0f, 1e-5f);
  EXPECT_NEAR(clip.y / clip.w, 0.0f, 1e-5f);
  EXPECT_GT(clip.w, 0.0f);
}

TEST(Camera, OrthographicHeightSpansTheImage) {
  const auto scene = Scene(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}}],
      "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 4,
                 "position": {"x": 0, "y": 0, "z": 5}, "up": {"x": 0, "y": 1, "z": 0}}})");
  const CameraMatrices camera = MakeCameraMatrices(scene.camera(), 2.0f);
  const glm::vec4 top = camera.projection * camera.view * glm::vec4(0.0f, 2.0f, 0.0f, 1.0f);
  const glm::vec4 right = camera.projection * camera.view * glm::vec4(4.0f, 0.0f, 0.0f, 1.0f);
  EXPECT_NEAR(top.y / top.w, 1.0f, 1e-5f);
  EXPECT_NEAR(right.x / right.w, 1.0f, 1e-5f);
}

}  // namespace
}  // namespace loom
