#include "core/animate/cloth_sequence_io.h"

#include <tiny_gltf.h>

#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>

#include "core/scene/mesh_preparation.h"
#include "core/scene/obj_writer.h"
#include "core/spec/limits.h"
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

// --- Reading -------------------------------------------------------------------

[[noreturn]] void Fail(const std::filesystem::path& path, const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, "glTF " + path.string() + ": " + what);
}

// The accessor's elements, each `components` values of type T (checked against
// its declared types), whatever its stride.
template <typename T>
std::vector<T> ReadAccessor(const tinygltf::Model& model, int index, int type, int component_type,
                            const std::filesystem::path& path, const std::string& what) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) Fail(path, what + ": no such accessor");
  const tinygltf::Accessor& accessor = model.accessors[index];
  if (accessor.type != type || accessor.componentType != component_type) {
    Fail(path, what + ": unexpected accessor type");
  }
  if (accessor.sparse.isSparse || accessor.bufferView < 0 ||
      accessor.bufferView >= static_cast<int>(model.bufferViews.size())) {
    Fail(path, what + ": sparse or bufferless accessors are not read");
  }
  const tinygltf::BufferView& view = model.bufferViews[accessor.bufferView];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) Fail(path, what + ": no such buffer");
  const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
  const int components = tinygltf::GetNumComponentsInType(type);
  const size_t element = components * sizeof(T);
  const int stride = accessor.ByteStride(view);
  if (stride < static_cast<int>(element)) Fail(path, what + ": bad byte stride");
  const size_t count = accessor.count;
  if (count > static_cast<size_t>(kMaxMeshVertices) * 3) Fail(path, what + ": too many elements");
  const size_t begin = view.byteOffset + accessor.byteOffset;
  const size_t end = count == 0 ? begin : begin + (count - 1) * static_cast<size_t>(stride) + element;
  if (end > view.byteOffset + view.byteLength || end > data.size()) Fail(path, what + ": runs past its buffer");
  std::vector<T> values(count * components);
  for (size_t i = 0; i < count; ++i) std::memcpy(&values[i * components], &data[begin + i * stride], element);
  return values;
}

std::vector<glm::vec3> ToVec3s(const std::vector<float>& values) {
  std::vector<glm::vec3> points(values.size() / 3);
  std::memcpy(points.data(), values.data(), points.size() * sizeof(glm::vec3));
  return points;
}

std::vector<uint32_t> ReadIndices(const tinygltf::Model& model, int index, const std::filesystem::path& path) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) Fail(path, "the primitive has no indices");
  switch (model.accessors[index].componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const auto v = ReadAccessor<uint8_t>(model, index, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                           path, "indices");
      return {v.begin(), v.end()};
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const auto v = ReadAccessor<uint16_t>(model, index, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                            path, "indices");
      return {v.begin(), v.end()};
    }
    default:
      return ReadAccessor<uint32_t>(model, index, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, path,
                                    "indices");
  }
}

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

TriangleMesh ClothMesh(const KnitCloth& cloth, const std::vector<glm::vec3>& positions) {
  TriangleMesh mesh = UnpreparedClothMesh(cloth, positions);
  PrepareMesh(mesh, "animated cloth");
  return mesh;
}

void WriteObjSequence(const ClothAnimation& animation, const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  for (size_t k = 0; k < animation.frames.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu.obj", k);
    WriteObj(ClothMesh(animation.cloth, animation.frames[k]), directory / name);
  }
}

void WriteGltfSequence(const ClothAnimation& animation, const std::filesystem::path& path) {
  if (animation.frames.empty()) throw Error(ErrorCode::kInvalidArgument, "glTF sequence: no frames");
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Loom";
  GltfBuilder builder(model);
  const std::vector<glm::vec3>& base = animation.frames[0];
  const size_t vertices = base.size();
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.attributes["POSITION"] = builder.Floats(&base[0].x, vertices, TINYGLTF_TYPE_VEC3, 3, true);
  const TriangleMesh mesh = UnpreparedClothMesh(animation.cloth, base);
  primitive.attributes["TEXCOORD_0"] = builder.Floats(&mesh.uvs[0].x, vertices, TINYGLTF_TYPE_VEC2, 2, false);
  primitive.indices = builder.Indices(mesh.indices);
  // Target k − 1 moves frame 0 to frame k.
  const size_t targets = animation.frames.size() - 1;
  std::vector<glm::vec3> delta(vertices);
  for (size_t k = 1; k <= targets; ++k) {
    for (size_t v = 0; v < vertices; ++v) delta[v] = animation.frames[k][v] - base[v];
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
    // Key k at k / rate: frame 0 has every weight 0, frame k weight 1 on target k − 1.
    std::vector<float> times(targets + 1), weights((targets + 1) * targets, 0.0f);
    for (size_t k = 0; k <= targets; ++k) {
      times[k] = static_cast<float>(k / double{animation.frames_per_second});
      if (k > 0) weights[k * targets + (k - 1)] = 1.0f;
    }
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

MeshSequence ReadGltfSequence(const std::filesystem::path& path) {
  const std::string bytes = ReadFile(path);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
  const bool loaded =
      binary
          ? loader.LoadBinaryFromMemory(&model, &error, &warning, reinterpret_cast<const unsigned char*>(bytes.data()),
                                        static_cast<unsigned>(bytes.size()), path.parent_path().string())
          : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), static_cast<unsigned>(bytes.size()),
                                       path.parent_path().string());
  if (!loaded) Fail(path, error.empty() ? "not a glTF file" : error);
  if (model.meshes.empty() || model.meshes[0].primitives.empty()) Fail(path, "no mesh");
  const tinygltf::Primitive& primitive = model.meshes[0].primitives[0];
  if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != -1) Fail(path, "the primitive is not triangles");
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) Fail(path, "the primitive has no POSITION");

  MeshSequence sequence;
  TriangleMesh& mesh = sequence.mesh;
  mesh.positions = ToVec3s(ReadAccessor<float>(model, position->second, TINYGLTF_TYPE_VEC3,
                                               TINYGLTF_COMPONENT_TYPE_FLOAT, path, "POSITION"));
  if (mesh.positions.size() > static_cast<size_t>(kMaxMeshVertices)) Fail(path, "too many vertices");
  if (const auto uv = primitive.attributes.find("TEXCOORD_0"); uv != primitive.attributes.end()) {
    const std::vector<float> values =
        ReadAccessor<float>(model, uv->second, TINYGLTF_TYPE_VEC2, TINYGLTF_COMPONENT_TYPE_FLOAT, path, "TEXCOORD_0");
    if (values.size() != 2 * mesh.positions.size()) Fail(path, "TEXCOORD_0 and POSITION differ in count");
    mesh.uvs.resize(mesh.positions.size());
    std::memcpy(mesh.uvs.data(), values.data(), values.size() * sizeof(float));
  }
  mesh.indices = ReadIndices(model, primitive.indices, path);
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) Fail(path, "the indices are not whole triangles");
  if (mesh.indices.size() / 3 > static_cast<size_t>(kMaxMeshTriangles)) Fail(path, "too many triangles");
  for (uint32_t index : mesh.indices) {
    if (index >= mesh.positions.size()) Fail(path, "an index past the last vertex");
  }

  std::vector<std::vector<glm::vec3>> deltas;
  for (size_t t = 0; t < primitive.targets.size(); ++t) {
    const auto target = primitive.targets[t].find("POSITION");
    if (target == primitive.targets[t].end()) Fail(path, "a morph target without POSITION");
    deltas.push_back(ToVec3s(ReadAccessor<float>(model, target->second, TINYGLTF_TYPE_VEC3,
                                                 TINYGLTF_COMPONENT_TYPE_FLOAT, path, "a morph target")));
    if (deltas.back().size() != mesh.positions.size()) Fail(path, "a morph target and POSITION differ in count");
  }
  const tinygltf::AnimationSampler* weights = nullptr;
  for (const tinygltf::Animation& animation : model.animations) {
    for (const tinygltf::AnimationChannel& channel : animation.channels) {
      if (channel.target_path == "weights" && channel.sampler >= 0 &&
          channel.sampler < static_cast<int>(animation.samplers.size())) {
        weights = &animation.samplers[channel.sampler];
      }
    }
  }
  if (weights == nullptr || deltas.empty()) {
    sequence.frames = {mesh.positions};
    sequence.times = {0.0f};
    return sequence;
  }
  sequence.times = ReadAccessor<float>(model, weights->input, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_FLOAT, path,
                                       "the animation's times");
  const std::vector<float> w = ReadAccessor<float>(model, weights->output, TINYGLTF_TYPE_SCALAR,
                                                   TINYGLTF_COMPONENT_TYPE_FLOAT, path, "the animation's weights");
  if (w.size() != sequence.times.size() * deltas.size()) Fail(path, "the weights are not one a target a key");
  if (sequence.times.size() * mesh.positions.size() > kMaxAnimationPoints) Fail(path, "too many frames");
  for (size_t k = 0; k < sequence.times.size(); ++k) {
    std::vector<glm::vec3> frame = mesh.positions;
    for (size_t t = 0; t < deltas.size(); ++t) {
      const float weight = w[k * deltas.size() + t];
      if (weight == 0.0f) continue;
      for (size_t v = 0; v < frame.size(); ++v) frame[v] += weight * deltas[t][v];
    }
    sequence.frames.push_back(std::move(frame));
  }
  return sequence;
}

}  // namespace loom::animate
