#include "core/scene/scene_geometry.h"

#include <gtest/gtest.h>

#include "core/scene/camera.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"

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

TEST(SceneGeometry, ObjErrorsNameTheObject) {
  const auto scene = Scene(R"({"objects": [{"name": "cloth", "mesh": {"obj_path": "flat.obj"}}],
      "camera": {"position": {"x": 0, "y": -3, "z": 1}}})");
  try {
    BuildSceneGeometry(scene, [](const v1::MeshRef&) { return std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"); });
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("scene.objects[0] (cloth)"), std::string::npos) << error.what();
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
