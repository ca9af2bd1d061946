#include "core/scene/scene_geometry.h"

#include <glm/gtc/matrix_transform.hpp>

#include "core/scene/builtin_shapes.h"
#include "core/scene/camera.h"
#include "core/scene/gltf_loader.h"
#include "core/scene/obj_loader.h"
#include "core/spec/limits.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

constexpr int kDefaultSegments = 64;

TriangleMesh BuiltinMesh(v1::BuiltinShape shape, int segments) {
  switch (shape) {
    case v1::BUILTIN_SHAPE_PLANE:
      return MakePlane(segments);
    case v1::BUILTIN_SHAPE_SPHERE:
      return MakeSphere(segments);
    case v1::BUILTIN_SHAPE_CYLINDER:
      return MakeCylinder(segments);
    case v1::BUILTIN_SHAPE_DRAPE:
      return MakeDrape(segments);
    default:
      break;
  }
  throw Error(ErrorCode::kInvalidArgument, "unknown built-in shape " + std::to_string(shape));
}

void Transform(TriangleMesh& mesh, const glm::mat4& model) {
  const glm::mat3 linear(model);
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
  for (glm::vec3& p : mesh.positions) p = glm::vec3(model * glm::vec4(p, 1.0f));
  for (glm::vec3& n : mesh.normals) n = glm::normalize(normal_matrix * n);
  // A mirroring transform flips the tangent frame's handedness.
  const float flip = glm::determinant(linear) < 0.0f ? -1.0f : 1.0f;
  for (glm::vec4& t : mesh.tangents) t = glm::vec4(glm::normalize(linear * glm::vec3(t)), t.w * flip);
}

// A built-in shape's share of the scene's caps (its segments are capped, but a
// scene may repeat it).
void CheckWithinLimits(const TriangleMesh& mesh, const MeshLimits& left, const std::string& label) {
  if (static_cast<int64_t>(mesh.triangle_count()) > left.triangles ||
      static_cast<int64_t>(mesh.positions.size()) > left.vertices) {
    throw Error(ErrorCode::kInvalidArgument, "mesh " + label + ": " + std::to_string(mesh.triangle_count()) +
                                                 " triangles and " + std::to_string(mesh.positions.size()) +
                                                 " vertices exceed what the scene's earlier objects left of " +
                                                 "its caps (" + std::to_string(kMaxMeshTriangles) + " triangles, " +
                                                 std::to_string(kMaxMeshVertices) + " vertices)");
  }
}

// A mesh file streamed in pieces: an OBJ parsed as it arrives, a glTF (by its
// first bytes, LooksLikeGltf) gathered whole and read at the end: only the frame
// asked for, or with `whole_sequence` every frame, kept in sequence().
class MeshFileParser {
 public:
  MeshFileParser(std::string label, const MeshLimits& left, const v1::MeshRef& ref, bool whole_sequence)
      : label_(std::move(label)),
        left_(left),
        frame_(ref.frame()),
        gltf_mesh_(ref.gltf_mesh()),
        whole_sequence_(whole_sequence) {}

  void Feed(std::string_view piece) {
    if (obj_) return obj_->Feed(piece);
    head_.append(piece);
    if (!gltf_ && head_.size() >= kSniffBytes) Decide();
  }

  TriangleMesh Finish() {
    if (!obj_ && !gltf_) Decide();
    if (obj_) {
      if (frame_ > 0) Fail("frame " + std::to_string(frame_) + " of an OBJ mesh (frames belong to glTF sequences)");
      if (!gltf_mesh_.empty()) Fail("gltf_mesh '" + gltf_mesh_ + "' of an OBJ mesh");
      return obj_->Finish();
    }
    TriangleMesh mesh;
    if (whole_sequence_) {
      sequence_ = std::make_shared<const MeshSequence>(ParseGltfSequence(head_, "mesh " + label_, gltf_mesh_));
      mesh = SequenceFrame(*sequence_, frame_, "mesh " + label_);
    } else {
      mesh = ParseGltfFrame(head_, frame_, "mesh " + label_, gltf_mesh_);
    }
    CheckWithinLimits(mesh, left_, label_);
    return mesh;
  }
  // The glTF's every frame, once Finish() has read them (whole_sequence only).
  std::shared_ptr<const MeshSequence> sequence() const { return sequence_; }

 private:
  // Enough to see "glTF", or a "{" behind some white space.
  static constexpr size_t kSniffBytes = 64;

  void Decide() {
    gltf_ = LooksLikeGltf(head_);
    if (gltf_) return;
    obj_ = std::make_unique<ObjParser>(label_, left_);
    obj_->Feed(std::exchange(head_, {}));
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw Error(ErrorCode::kInvalidArgument, "mesh " + label_ + ": " + what);
  }

  const std::string label_;
  const MeshLimits left_;
  const uint32_t frame_;
  const std::string gltf_mesh_;
  const bool whole_sequence_;
  std::shared_ptr<const MeshSequence> sequence_;
  std::string head_;  // the bytes so far, until the format is known; all of a glTF's
  bool gltf_ = false;
  std::unique_ptr<ObjParser> obj_;
};

}  // namespace

MeshTextResolver FileMeshResolver(const std::filesystem::path& scene_directory) {
  return [scene_directory](const v1::MeshRef& mesh, const TextSink& consume) {
    if (mesh.source_case() == v1::MeshRef::kObjPath)
      return ReadFileInPieces(scene_directory / mesh.obj_path(), consume);
    if (mesh.source_case() == v1::MeshRef::kGltfPath) {
      return ReadFileInPieces(scene_directory / mesh.gltf_path(), consume);
    }
    throw Error(ErrorCode::kInvalidArgument, "mesh artifacts are resolved by the server, not from files");
  };
}

Bounds SceneGeometryBounds(const std::vector<SceneMesh>& meshes) {
  Bounds bounds;
  for (const SceneMesh& mesh : meshes) bounds.Add(mesh.mesh.positions);
  return bounds;
}

glm::mat4 ModelMatrix(const v1::Transform& transform) {
  const glm::vec3 degrees = ToGlm(transform.rotation_degrees());
  glm::mat4 model = glm::translate(glm::mat4(1.0f), ToGlm(transform.translation()));
  model = glm::rotate(model, glm::radians(degrees.z), glm::vec3(0, 0, 1));
  model = glm::rotate(model, glm::radians(degrees.y), glm::vec3(0, 1, 0));
  model = glm::rotate(model, glm::radians(degrees.x), glm::vec3(1, 0, 0));
  return glm::scale(model, ToGlm(transform.scale()));
}

std::vector<SceneMesh> BuildSceneGeometry(const v1::SceneSpec& scene, const MeshTextResolver& resolve,
                                          MeshSequenceCache* sequences) {
  std::vector<SceneMesh> meshes;
  MeshLimits left;  // what the objects so far have left of the scene's caps
  for (int i = 0; i < scene.objects_size(); ++i) {
    const v1::SceneObject& object = scene.objects(i);
    const std::string label =
        "scene.objects[" + std::to_string(i) + "]" + (object.name().empty() ? "" : " (" + object.name() + ")");
    SceneMesh built;
    built.object = &object;
    const v1::MeshRef& ref = object.mesh();
    const int segments = ref.segments() > 0 ? static_cast<int>(ref.segments()) : kDefaultSegments;
    if (ref.source_case() == v1::MeshRef::kBuiltin) {
      built.mesh = BuiltinMesh(ref.builtin(), segments);
      CheckWithinLimits(built.mesh, left, label);
    } else {
      // Only artifacts are kept: their content never changes under their name.
      const bool keep = sequences && ref.source_case() == v1::MeshRef::kArtifact;
      if (const auto kept = keep ? sequences->Find(ref.artifact(), ref.gltf_mesh()) : nullptr) {
        built.mesh = SequenceFrame(*kept, ref.frame(), "mesh " + label);
        CheckWithinLimits(built.mesh, left, label);
      } else {
        MeshFileParser parser(label, left, ref, keep);
        resolve(ref, [&parser](std::string_view piece) { parser.Feed(piece); });
        built.mesh = parser.Finish();
        if (parser.sequence()) sequences->Keep(ref.artifact(), ref.gltf_mesh(), parser.sequence());
      }
    }
    left.triangles -= static_cast<int64_t>(built.mesh.triangle_count());
    left.vertices -= static_cast<int64_t>(built.mesh.positions.size());
    if (object.has_fabric() && built.mesh.uvs.empty()) {
      throw Error(
          ErrorCode::kInvalidArgument,
          "mesh " + label + ": has no texture coordinates (vt): a fabric is tiled over the mesh through its UVs");
    }
    built.report = PrepareMesh(built.mesh, label.c_str());
    Transform(built.mesh, ModelMatrix(object.transform()));
    meshes.push_back(std::move(built));
  }
  return meshes;
}

}  // namespace loom
