#include "core/animate/cloth_sequence_io.h"

#include <tiny_gltf.h>

#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

#include "core/scene/builtin_shapes.h"
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

// A sphere's segments in its mesh.
constexpr int kSolidSegments = 24;

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

std::vector<RigidTrack> SolidTracks(const ClothAnimation& animation) {
  std::vector<RigidTrack> solids;
  for (size_t k = 0; k < animation.colliders.size(); ++k) {
    const Collider& collider = animation.colliders[k];
    if (!collider.sphere()) continue;
    RigidTrack track{"collider_" + std::to_string(k), MakeSphere(kSolidSegments), animation.collider_tracks.at(k)};
    for (glm::vec3& p : track.mesh.positions) p = collider.centre() + collider.radius() * p;
    solids.push_back(std::move(track));
  }
  return solids;
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

void WriteGltfSequence(const MeshSequence& sequence, const std::filesystem::path& path,
                       const std::vector<RigidTrack>& solids) {
  if (sequence.frames.empty() || sequence.times.size() != sequence.frames.size()) {
    throw Error(ErrorCode::kInvalidArgument, "glTF sequence: no frames, or not one time a frame");
  }
  for (const RigidTrack& solid : solids) {
    if (solid.displacements.size() != sequence.frames.size()) {
      throw Error(ErrorCode::kInvalidArgument, "glTF sequence: " + solid.name + " has not one displacement a frame");
    }
  }
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Loom";
  GltfBuilder builder(model);
  tinygltf::Scene scene;
  // A mesh of the positions, the mesh's uvs and triangles, on a node of its own.
  const auto add_mesh = [&](const std::string& name, const TriangleMesh& mesh,
                            const std::vector<glm::vec3>& positions) {
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.attributes["POSITION"] = builder.Floats(&positions[0].x, positions.size(), TINYGLTF_TYPE_VEC3, 3, true);
    if (mesh.uvs.size() == positions.size()) {
      primitive.attributes["TEXCOORD_0"] =
          builder.Floats(&mesh.uvs[0].x, positions.size(), TINYGLTF_TYPE_VEC2, 2, false);
    }
    primitive.indices = builder.Indices(mesh.indices);
    tinygltf::Mesh gltf_mesh;
    gltf_mesh.name = name;
    gltf_mesh.primitives.push_back(primitive);
    model.meshes.push_back(gltf_mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = static_cast<int>(model.meshes.size()) - 1;
    model.nodes.push_back(node);
    scene.nodes.push_back(static_cast<int>(model.nodes.size()) - 1);
    return scene.nodes.back();
  };
  const std::vector<glm::vec3>& base = sequence.frames[0];
  const int cloth = add_mesh("cloth", sequence.mesh, base);
  // Target k − 1 moves frame 0 to frame k.
  const size_t targets = sequence.frames.size() - 1;
  tinygltf::Primitive& primitive = model.meshes[0].primitives[0];
  std::vector<glm::vec3> delta(base.size());
  for (size_t k = 1; k <= targets; ++k) {
    for (size_t v = 0; v < base.size(); ++v) delta[v] = sequence.frames[k][v] - base[v];
    primitive.targets.push_back({{"POSITION", builder.Floats(&delta[0].x, delta.size(), TINYGLTF_TYPE_VEC3, 3, true)}});
  }
  model.meshes[0].weights.assign(targets, 0.0);
  // Where a solid starts (its displacement at frame 0 is where its motion starts: none).
  std::vector<int> solid_nodes;
  for (const RigidTrack& solid : solids) solid_nodes.push_back(add_mesh(solid.name, solid.mesh, solid.mesh.positions));
  tinygltf::Animation animation;
  animation.name = "knit";
  if (targets > 0) {
    const int times = builder.Floats(sequence.times.data(), sequence.times.size(), TINYGLTF_TYPE_SCALAR, 1, true);
    const auto play = [&](int node, const std::string& path, int output) {
      tinygltf::AnimationSampler sampler;
      sampler.input = times;
      sampler.output = output;
      sampler.interpolation = "LINEAR";
      animation.samplers.push_back(sampler);
      tinygltf::AnimationChannel channel;
      channel.sampler = static_cast<int>(animation.samplers.size()) - 1;
      channel.target_node = node;
      channel.target_path = path;
      animation.channels.push_back(channel);
    };
    // Key k at frame k's time: frame 0 has every weight 0, frame k weight 1 on target k − 1.
    std::vector<float> weights((targets + 1) * targets, 0.0f);
    for (size_t k = 1; k <= targets; ++k) weights[k * targets + (k - 1)] = 1.0f;
    play(cloth, "weights", builder.Floats(weights.data(), weights.size(), TINYGLTF_TYPE_SCALAR, 1, false));
    for (size_t i = 0; i < solids.size(); ++i) {
      const std::vector<glm::vec3>& moved = solids[i].displacements;
      play(solid_nodes[i], "translation", builder.Floats(&moved[0].x, moved.size(), TINYGLTF_TYPE_VEC3, 3, false));
    }
    model.animations.push_back(animation);
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;
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
