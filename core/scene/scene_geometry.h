#pragma once
// A scene's objects as world-space meshes, ready for the renderers: each object's
// mesh resolved (built-in, OBJ, glTF), prepared (core/scene/mesh_preparation.h) and
// transformed.

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/scene/mesh_preparation.h"
#include "core/scene/mesh_sequence_cache.h"
#include "core/scene/triangle_mesh.h"
#include "loom/v1/scene.pb.h"

namespace loom {

struct SceneMesh {
  const v1::SceneObject* object = nullptr;  // points into the SceneSpec given to BuildSceneGeometry
  TriangleMesh mesh;                        // world space
  MeshPreparationReport report;
};

// Streams the bytes of a mesh given by obj_path, gltf_path or artifact to
// `consume`, in pieces of any size, so that a large OBJ is parsed as it is read (a
// glTF is read whole; its first bytes tell it from an OBJ). Front ends
// decide what may be opened: loom-lab reads files next to the scene, the server
// reads uploaded artifacts only.
using TextSink = std::function<void(std::string_view piece)>;
using MeshTextResolver = std::function<void(const v1::MeshRef& mesh, const TextSink& consume)>;

// Reads obj_path or gltf_path relative to `scene_directory` in 1 MiB pieces;
// refuses artifacts.
MeshTextResolver FileMeshResolver(const std::filesystem::path& scene_directory);

// `scene` with defaults applied and validated. Errors name the object. Every
// object's mesh counts towards one MeshLimits (core/scene/obj_loader.h): the
// scene's triangles and vertices together stay within the caps, whatever its
// objects repeat. An object with a fabric needs texture coordinates; one without
// may have none (it is plain diffuse). With `sequences`, a glTF artifact's
// sequence is taken from it when kept there, and kept there when read.
std::vector<SceneMesh> BuildSceneGeometry(const v1::SceneSpec& scene, const MeshTextResolver& resolve,
                                          MeshSequenceCache* sequences = nullptr);

// The bounding box of every mesh of a scene.
Bounds SceneGeometryBounds(const std::vector<SceneMesh>& meshes);

// Model matrix of a Transform: translate · rotate Z · rotate Y · rotate X · scale.
glm::mat4 ModelMatrix(const v1::Transform& transform);

}  // namespace loom
