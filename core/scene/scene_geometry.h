#pragma once
// A scene's objects as world-space meshes, ready for the renderers: each object's
// mesh resolved (built-in, OBJ), prepared (core/scene/mesh_preparation.h) and
// transformed.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/scene/mesh_preparation.h"
#include "core/scene/triangle_mesh.h"
#include "loom/v1/scene.pb.h"

namespace loom {

struct SceneMesh {
  const v1::SceneObject* object = nullptr;  // points into the SceneSpec given to BuildSceneGeometry
  TriangleMesh mesh;                        // world space
  MeshPreparationReport report;
};

// Returns the OBJ text of a mesh given by obj_path or artifact. Front ends decide
// what may be opened: loom-lab reads files next to the scene, the server reads
// uploaded artifacts only.
using MeshTextResolver = std::function<std::string(const v1::MeshRef& mesh)>;

// Reads obj_path relative to `scene_directory`; refuses artifacts.
MeshTextResolver FileMeshResolver(const std::filesystem::path& scene_directory);

// `scene` with defaults applied and validated. Errors name the object.
std::vector<SceneMesh> BuildSceneGeometry(const v1::SceneSpec& scene, const MeshTextResolver& resolve);

// The bounding box of every mesh of a scene.
Bounds SceneGeometryBounds(const std::vector<SceneMesh>& meshes);

// Model matrix of a Transform: translate · rotate Z · rotate Y · rotate X · scale.
glm::mat4 ModelMatrix(const v1::Transform& transform);

}  // namespace loom
