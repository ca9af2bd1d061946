#include "core/scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "core/spec/limits.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

[[noreturn]] void Fail(const std::filesystem::path& path, const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, "glTF " + path.string() + ": " + what);
}

// An accessor's elements checked against its declared types and its buffer, each
// `components` values of type T, whatever its stride; Copy() reads them.
template <typename T>
struct AccessorView {
  const unsigned char* begin = nullptr;
  size_t stride = 0, count = 0;
  int components = 0;

  std::vector<T> Copy() const {
    std::vector<T> values(count * components);
    for (size_t i = 0; i < count; ++i) {
      std::memcpy(&values[i * components], begin + i * stride, components * sizeof(T));
    }
    return values;
  }
};

template <typename T>
AccessorView<T> ViewAccessor(const tinygltf::Model& model, int index, int type, int component_type,
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
  AccessorView<T> result;
  result.components = tinygltf::GetNumComponentsInType(type);
  const size_t element = result.components * sizeof(T);
  const int stride = accessor.ByteStride(view);
  if (stride < static_cast<int>(element)) Fail(path, what + ": bad byte stride");
  result.stride = static_cast<size_t>(stride);
  result.count = accessor.count;
  if (result.count > static_cast<size_t>(kMaxMeshVertices) * 3) Fail(path, what + ": too many elements");
  const size_t begin = view.byteOffset + accessor.byteOffset;
  const size_t end = result.count == 0 ? begin : begin + (result.count - 1) * result.stride + element;
  if (end > view.byteOffset + view.byteLength || end > data.size()) Fail(path, what + ": runs past its buffer");
  result.begin = data.data() + begin;
  return result;
}

template <typename T>
std::vector<T> ReadAccessor(const tinygltf::Model& model, int index, int type, int component_type,
                            const std::filesystem::path& path, const std::string& what) {
  return ViewAccessor<T>(model, index, type, component_type, path, what).Copy();
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

// Uploaded bytes name no files the reader may open, and their images are not
// decoded (a mesh needs none).
bool RefuseFile(std::vector<unsigned char>*, std::string* error, const std::string& name, void*) {
  *error = "refers to the file '" + name + "'; an uploaded glTF must hold its buffers (a .glb, or data: URIs)";
  return false;
}
bool SkipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

// A parsed glTF mesh's first primitive and its morph-target and translation
// animations, whose frames are made one at a time (a render needs one of perhaps
// thousands).
class GltfSequence {
 public:
  // `base` is the directory of a local file (its external buffers are read from
  // there), or nothing for uploaded bytes.
  GltfSequence(const std::string& bytes, const std::filesystem::path& path,
               const std::optional<std::filesystem::path>& base, const std::string& mesh_name)
      : path_(path) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(SkipImage, nullptr);
    if (!base) {
      loader.SetFsCallbacks({[](const std::string&, void*) { return true; },
                             [](const std::string& name, void*) { return name; }, RefuseFile, nullptr, nullptr});
    }
    std::string error, warning;
    const std::string base_dir = base ? base->string() : "";
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    if (bytes.size() > std::numeric_limits<unsigned>::max()) Fail(path, "larger than 4 GiB");
    const bool loaded = binary ? loader.LoadBinaryFromMemory(&model_, &error, &warning,
                                                             reinterpret_cast<const unsigned char*>(bytes.data()),
                                                             static_cast<unsigned>(bytes.size()), base_dir)
                               : loader.LoadASCIIFromString(&model_, &error, &warning, bytes.data(),
                                                            static_cast<unsigned>(bytes.size()), base_dir);
    if (!loaded) Fail(path, error.empty() ? "not a glTF file" : error);
    const int mesh = FindMesh(mesh_name);
    if (model_.meshes[mesh].primitives.empty()) Fail(path, "no mesh");
    const tinygltf::Primitive& primitive = model_.meshes[mesh].primitives[0];
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != -1) Fail(path, "the primitive is not triangles");
    ReadMesh(primitive);
    ReadAnimation(primitive, mesh);
  }

  const TriangleMesh& mesh() const { return mesh_; }
  const std::vector<float>& times() const { return times_; }
  size_t FrameCount() const { return times_.size(); }

  // Frame k's positions: frame 0's plus each target's offset by its weight at key
  // k, moved by the translation at key k.
  std::vector<glm::vec3> Positions(size_t k) const {
    std::vector<glm::vec3> frame = mesh_.positions;
    for (size_t t = 0; t < targets_.size(); ++t) {
      const float weight = weights_[k * targets_.size() + t];
      if (weight == 0.0f) continue;
      const std::vector<glm::vec3> delta = ToVec3s(targets_[t].Copy());
      for (size_t v = 0; v < frame.size(); ++v) frame[v] += weight * delta[v];
    }
    if (!translations_.empty()) {
      for (glm::vec3& p : frame) p += translations_[k];
    }
    return frame;
  }

 private:
  // The mesh named `name`, or the first when it is empty.
  int FindMesh(const std::string& name) const {
    if (model_.meshes.empty()) Fail(path_, "no mesh");
    if (name.empty()) return 0;
    std::string names;
    for (size_t m = 0; m < model_.meshes.size(); ++m) {
      if (model_.meshes[m].name == name) return static_cast<int>(m);
      names += (m == 0 ? "" : ", ") + ("'" + model_.meshes[m].name + "'");
    }
    Fail(path_, "no mesh named '" + name + "' (it has " + names + ")");
  }

  void ReadMesh(const tinygltf::Primitive& primitive) {
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) Fail(path_, "the primitive has no POSITION");
    mesh_.positions = ToVec3s(ReadAccessor<float>(model_, position->second, TINYGLTF_TYPE_VEC3,
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, path_, "POSITION"));
    if (mesh_.positions.size() > static_cast<size_t>(kMaxMeshVertices)) Fail(path_, "too many vertices");
    if (const auto uv = primitive.attributes.find("TEXCOORD_0"); uv != primitive.attributes.end()) {
      const std::vector<float> values = ReadAccessor<float>(model_, uv->second, TINYGLTF_TYPE_VEC2,
                                                            TINYGLTF_COMPONENT_TYPE_FLOAT, path_, "TEXCOORD_0");
      if (values.size() != 2 * mesh_.positions.size()) Fail(path_, "TEXCOORD_0 and POSITION differ in count");
      mesh_.uvs.resize(mesh_.positions.size());
      std::memcpy(mesh_.uvs.data(), values.data(), values.size() * sizeof(float));
    }
    mesh_.indices = ReadIndices(model_, primitive.indices, path_);
    if (mesh_.indices.empty() || mesh_.indices.size() % 3 != 0) Fail(path_, "the indices are not whole triangles");
    if (mesh_.indices.size() / 3 > static_cast<size_t>(kMaxMeshTriangles)) Fail(path_, "too many triangles");
    for (uint32_t index : mesh_.indices) {
      if (index >= mesh_.positions.size()) Fail(path_, "an index past the last vertex");
    }
  }

  // The animations of the first node showing the mesh: the morph targets and
  // the weights animation that plays them, and a translation animation; without
  // either, the mesh is a sequence of one frame at time 0. Both, they must have
  // the same keys.
  void ReadAnimation(const tinygltf::Primitive& primitive, int mesh) {
    int node = -1;
    for (size_t n = 0; n < model_.nodes.size() && node < 0; ++n) {
      if (model_.nodes[n].mesh == mesh) node = static_cast<int>(n);
    }
    const tinygltf::AnimationSampler *weights = nullptr, *translation = nullptr;
    for (const tinygltf::Animation& animation : model_.animations) {
      for (const tinygltf::AnimationChannel& channel : animation.channels) {
        if (node < 0 || channel.target_node != node || channel.sampler < 0 ||
            channel.sampler >= static_cast<int>(animation.samplers.size())) {
          continue;
        }
        if (channel.target_path == "weights") weights = &animation.samplers[channel.sampler];
        if (channel.target_path == "translation") translation = &animation.samplers[channel.sampler];
      }
    }
    times_ = {0.0f};
    if (translation != nullptr) {
      times_ = ReadAccessor<float>(model_, translation->input, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                   path_, "the translation's times");
      translations_ = ToVec3s(ReadAccessor<float>(model_, translation->output, TINYGLTF_TYPE_VEC3,
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, path_, "the translations"));
      if (translations_.size() != times_.size()) Fail(path_, "the translations are not one a key");
    }
    if (weights == nullptr || primitive.targets.empty()) {
      if (times_.size() * mesh_.positions.size() > kMaxAnimationPoints) Fail(path_, "too many frames");
      return;
    }
    for (const auto& target : primitive.targets) {
      const auto position = target.find("POSITION");
      if (position == target.end()) Fail(path_, "a morph target without POSITION");
      targets_.push_back(ViewAccessor<float>(model_, position->second, TINYGLTF_TYPE_VEC3,
                                             TINYGLTF_COMPONENT_TYPE_FLOAT, path_, "a morph target"));
      if (targets_.back().count != mesh_.positions.size()) Fail(path_, "a morph target and POSITION differ in count");
    }
    const std::vector<float> times = ReadAccessor<float>(model_, weights->input, TINYGLTF_TYPE_SCALAR,
                                                         TINYGLTF_COMPONENT_TYPE_FLOAT, path_, "the animation's times");
    if (translation != nullptr && times != times_) Fail(path_, "the weights and the translation have different keys");
    times_ = times;
    weights_ = ReadAccessor<float>(model_, weights->output, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_FLOAT, path_,
                                   "the animation's weights");
    if (weights_.size() != times_.size() * targets_.size()) Fail(path_, "the weights are not one a target a key");
    if (times_.size() * mesh_.positions.size() > kMaxAnimationPoints) Fail(path_, "too many frames");
  }

  const std::filesystem::path path_;
  tinygltf::Model model_;
  TriangleMesh mesh_;
  std::vector<AccessorView<float>> targets_;  // into model_'s buffers
  std::vector<float> times_, weights_;        // weights_: one a target a key
  std::vector<glm::vec3> translations_;       // one a key, or none
};

MeshSequence WholeSequence(const GltfSequence& gltf) {
  MeshSequence sequence;
  sequence.mesh = gltf.mesh();
  sequence.times = gltf.times();
  for (size_t k = 0; k < gltf.FrameCount(); ++k) sequence.frames.push_back(gltf.Positions(k));
  return sequence;
}

void CheckFrame(size_t frame, size_t frames, const std::string& name) {
  if (frame >= frames) {
    throw Error(ErrorCode::kInvalidArgument, name + ": frame " + std::to_string(frame) + " of a sequence of " +
                                                 std::to_string(frames) + " frame(s)");
  }
}

}  // namespace

MeshSequence ReadGltfSequence(const std::filesystem::path& path, const std::string& mesh_name) {
  return WholeSequence(GltfSequence(ReadFile(path), path, path.parent_path(), mesh_name));
}

MeshSequence ParseGltfSequence(const std::string& bytes, const std::string& name, const std::string& mesh_name) {
  return WholeSequence(GltfSequence(bytes, name, std::nullopt, mesh_name));
}

TriangleMesh ParseGltfFrame(const std::string& bytes, size_t frame, const std::string& name,
                            const std::string& mesh_name) {
  const GltfSequence gltf(bytes, name, std::nullopt, mesh_name);
  CheckFrame(frame, gltf.FrameCount(), name);
  TriangleMesh mesh = gltf.mesh();
  mesh.positions = gltf.Positions(frame);
  return mesh;
}

TriangleMesh SequenceFrame(const MeshSequence& sequence, size_t frame, const std::string& name) {
  CheckFrame(frame, sequence.frames.size(), name);
  TriangleMesh mesh;
  mesh.positions = sequence.frames[frame];
  mesh.uvs = sequence.mesh.uvs;
  mesh.indices = sequence.mesh.indices;
  return mesh;
}

bool LooksLikeGltf(std::string_view head) {
  if (head.starts_with("glTF")) return true;
  const size_t first = head.find_first_not_of(" \t\r\n");
  return first != std::string_view::npos && head[first] == '{';
}

}  // namespace loom
