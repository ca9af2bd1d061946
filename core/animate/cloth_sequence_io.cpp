#include "core/animate/cloth_sequence_io.h"

#include <tiny_gltf.h>

#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

#include "core/scene/mesh_preparation.h"
#include "core/scene/obj_writer.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::animate {
namespace {

// --- Writing -------------------------------------------------------------------

// Appends views and accessors to one buffer.
class GltfBuilder {
 public:
  explicit GltfBuilder(tinygltf::Model& model) : model_(model) { model_.buffers.emplace_back(); }

  int Floats(const float* values, size_t count, int type, int components, bool bounds) {
    const int view = View(values, count * components * sizeof(float));
    tinygltf::Accessor accessor;
    accessor.bufferView = view;
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.count = count;
    accessor.type = type;
    if (bounds) {
      accessor.minValues.assign(components, std::numeric_limits<double>::infinity());
      accessor.maxValues.assign(components, -std::numeric_limits<double>::infinity());
      for (size_t i = 0; i < count; ++i) {
        for (int c = 0; c < components; ++c) {
          accessor.minValues[c] = std::min<double>(accessor.minValues[c], values[i * components + c]);
          accessor.maxValues[c] = std::max<double>(accessor.maxValues[c], values[i * components + c]);
        }
      }
    }
    model_.accessors.push_back(accessor);
    return static_cast<int>(model_.accessors.size()) - 1;
  }

  int Indices(const std::vector<uint32_t>& indices) {
    tinygltf::Accessor accessor;
    accessor.bufferView = View(indices.data(), indices.size() * sizeof(uint32_t));
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.count = indices.size();
    accessor.type = TINYGLTF_TYPE_SCALAR;
    model_.accessors.push_back(accessor);
    return static_cast<int>(model_.accessors.size()) - 1;
  }

 private:
  int View(const void* bytes, size_t size) {
    std::vector<unsigned char>& data = model_.buffers[0].data;
    data.resize((data.size() + 3) / 4 * 4, 0);  // accessors align to their component size
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    data.insert(data.end(), static_cast<const unsigned char*>(bytes), static_cast<const unsigned char*>(bytes) + size);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  tinygltf::Model& model_;
};

// The cloth's positions, uvs and triangles, without normals (every triangle
// kept, degenerate or not).
TriangleMesh UnpreparedClothMesh(const KnitCloth& cloth, const std::vector<glm::vec3>& positions) {
  TriangleMesh mesh;
  mesh.positions = positions;
  mesh.uvs.reserve(positions.size());
  for (int j = 0; j < cloth.along; ++j) {
    for (int i = 0; i < cloth.across; ++i) {
      mesh.uvs.emplace_back(static_cast<float>(i) / (cloth.across - 1), static_cast<float>(j) / (cloth.along - 1));
    }
  }
  for (const glm::uvec3& t : cloth.Triangles()) mesh.indices.insert(mesh.indices.end(), {t.x, t.y, t.z});
  return mesh;
}

}  // namespace

MeshSequence ClothSequence(const ClothAnimation& animation) {
  if (animation.frames.empty()) throw Error(ErrorCode::kInvalidArgument, "cloth sequence: no frames");
  MeshSequence sequence;
  sequence.mesh = UnpreparedClothMesh(animation.cloth, animation.frames[0]);
  sequence.frames = animation.frames;
  for (size_t k = 0; k < animation.frames.size(); ++k) {
    sequence.times.push_back(static_cast<float>(k / double{animation.frames_per_second}));
  }
  return sequence;
}

void WriteObjSequence(const MeshSequence& sequence, const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  for (size_t k = 0; k < sequence.frames.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu.obj", k);
    TriangleMesh mesh = SequenceFrame(sequence, k, name);
    PrepareMesh(mesh, name);
    WriteObj(mesh, directory / name);
  }
}

void WriteGltfSequence(const MeshSequence& sequence, const std::filesystem::path& path) {
  if (sequence.frames.empty() || sequence.times.size() != sequence.frames.size()) {
    throw Error(ErrorCode::kInvalidArgument, "glTF sequence: no frames, or not one time a frame");
  }
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Loom";
  GltfBuilder builder(model);
  const std::vector<glm::vec3>& base = sequence.frames[0];
  const size_t vertices = base.size();
  const TriangleMesh& mesh = sequence.mesh;
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.attributes["POSITION"] = builder.Floats(&base[0].x, vertices, TINYGLTF_TYPE_VEC3, 3, true);
  if (mesh.uvs.size() == vertices) {
    primitive.attributes["TEXCOORD_0"] = builder.Floats(&mesh.uvs[0].x, vertices, TINYGLTF_TYPE_VEC2, 2, false);
  }
  primitive.indices = builder.Indices(mesh.indices);
  // Target k − 1 moves frame 0 to frame k.
  const size_t targets = sequence.frames.size() - 1;
  std::vector<glm::vec3> delta(vertices);
  for (size_t k = 1; k <= targets; ++k) {
    for (size_t v = 0; v < vertices; ++v) delta[v] = sequence.frames[k][v] - base[v];
    primitive.targets.push_back({{"POSITION", builder.Floats(&delta[0].x, vertices, TINYGLTF_TYPE_VEC3, 3, true)}});
  }
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = "cloth";
  gltf_mesh.primitives.push_back(primitive);
  gltf_mesh.weights.assign(targets, 0.0);
  model.meshes.push_back(gltf_mesh);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  if (targets > 0) {
    // Key k at frame k's time: frame 0 has every weight 0, frame k weight 1 on target k − 1.
    std::vector<float> times = sequence.times, weights((targets + 1) * targets, 0.0f);
    for (size_t k = 1; k <= targets; ++k) weights[k * targets + (k - 1)] = 1.0f;
    tinygltf::AnimationSampler sampler;
    sampler.input = builder.Floats(times.data(), times.size(), TINYGLTF_TYPE_SCALAR, 1, true);
    sampler.output = builder.Floats(weights.data(), weights.size(), TINYGLTF_TYPE_SCALAR, 1, false);
    sampler.interpolation = "LINEAR";
    tinygltf::AnimationChannel channel;
    channel.sampler = 0;
    channel.target_node = 0;
    channel.target_path = "weights";
    tinygltf::Animation gltf_animation;
    gltf_animation.name = "knit";
    gltf_animation.samplers.push_back(sampler);
    gltf_animation.channels.push_back(channel);
    model.animations.push_back(gltf_animation);
  }
  model.buffers[0].data.resize((model.buffers[0].data.size() + 3) / 4 * 4, 0);
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  const bool binary = path.extension() != ".gltf";
  if (!writer.WriteGltfSceneToStream(&model, out, false, binary)) {
    throw Error(ErrorCode::kInternal, "glTF " + path.string() + ": writing failed");
  }
  WriteFileAtomic(path, out.str());
}

}  // namespace loom::animate
