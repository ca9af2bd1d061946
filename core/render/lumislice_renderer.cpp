#include "core/render/lumislice_renderer.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

#include "core/acquire/kajiya_kay_brdf.h"
#include "core/fabric/yarn_material.h"
#include "core/gl/gpu_timer.h"
#include "core/gl/mesh_buffer.h"
#include "core/render/scene_lights.h"
#include "core/render/yarn_shadow.h"
#include "core/render/yarn_shadow_map.h"
#include "core/scene/scene_light.h"
#include "core/scene/camera.h"
#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

constexpr int kShadowUnit = 0;
constexpr int kDepthUnit = 1;
constexpr int kVrfUnit = 2;
constexpr int kDensityUnit = 3;
constexpr int kYarnShadowUnit = 4;
constexpr int kMaxAtlasYarns = 16;  // as the yarn arrays of lumislice.frag
constexpr int kLongitudeSpan = kLumisliceLongitudes + 1;

// One segment as lumislice_segment.glsl reads it.
struct GpuSegment {
  glm::vec4 start, end, normal, start_plane, end_plane, shading;
};

struct SortedSegment {
  float distance;
  uint64_t order;  // its place in the skeleton: ties keep it
  GpuSegment segment;
};

// The unit cube's triangles, counter-clockwise seen from outside; corner c is
// (c & 1, c >> 1 & 1, c >> 2 & 1) (lumislice.vert).
constexpr GLuint kBoxIndices[36] = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                                    2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};

// Every yarn's lumislice in two textures (lumislice.frag AtlasTexel): levels side by
// side in x, each with a border of empty voxels, yarns stacked in y; the VRF's
// directions in z, each longitude row followed by its first entry again.
class LumisliceAtlas {
 public:
  LumisliceAtlas(const std::vector<const Lumislice*>& yarns, int resolution) {
    const int levels = static_cast<int>(yarns.front()->levels.size());
    width_ = 0;
    for (int l = 0; l < levels; ++l) width_ += (resolution >> l) + 2;
    height_ = static_cast<int>(yarns.size()) * (resolution + 2);
    const int depth = kLongitudeSpan * kLumisliceAltitudes;
    std::vector<glm::vec4> vrf(static_cast<size_t>(width_) * height_ * depth, glm::vec4(0.0f));
    std::vector<float> density(static_cast<size_t>(width_) * height_, 0.0f);
    for (size_t y = 0; y < yarns.size(); ++y) {
      int x0 = 0;
      for (int l = 0; l < levels; ++l) {
        const LumisliceLevel& level = yarns[y]->levels[static_cast<size_t>(l)];
        for (int j = 0; j < level.resolution; ++j) {
          for (int i = 0; i < level.resolution; ++i) {
            const size_t voxel = static_cast<size_t>(j) * level.resolution + i;
            const size_t texel = static_cast<size_t>(static_cast<int>(y) * (resolution + 2) + 1 + j) * width_ +
                                 static_cast<size_t>(x0 + 1 + i);
            density[texel] = level.density[voxel];
            for (int a = 0; a < kLumisliceAltitudes; ++a) {
              for (int k = 0; k < kLongitudeSpan; ++k) {
                const int direction = (k % kLumisliceLongitudes) + kLumisliceLongitudes * a;
                vrf[static_cast<size_t>(a * kLongitudeSpan + k) * width_ * height_ + texel] =
                    level.at(direction, voxel);
              }
            }
          }
        }
        x0 += (resolution >> l) + 2;
      }
    }
    glCreateTextures(GL_TEXTURE_3D, 1, &vrf_);
    glTextureStorage3D(vrf_, 1, GL_RGBA8, width_, height_, depth);
    glTextureSubImage3D(vrf_, 0, 0, 0, 0, width_, height_, depth, GL_RGBA, GL_FLOAT, vrf.data());
    glCreateTextures(GL_TEXTURE_2D, 1, &density_);
    glTextureStorage2D(density_, 1, GL_R8, width_, height_);
    glTextureSubImage2D(density_, 0, 0, 0, width_, height_, GL_RED, GL_FLOAT, density.data());
    for (const GLuint texture : {vrf_, density_}) {
      glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      glTextureParameteri(texture, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    }
  }
  ~LumisliceAtlas() {
    glDeleteTextures(1, &vrf_);
    glDeleteTextures(1, &density_);
  }
  LumisliceAtlas(const LumisliceAtlas&) = delete;
  LumisliceAtlas& operator=(const LumisliceAtlas&) = delete;

  void Bind() const {
    glBindTextureUnit(kVrfUnit, vrf_);
    glBindTextureUnit(kDensityUnit, density_);
  }

 private:
  int width_ = 0, height_ = 0;
  GLuint vrf_ = 0, density_ = 0;
};

// The segments in drawing order and their yarn shadows (bindings 0 and 1 of
// lumislice_segment.glsl and lumislice.frag), bound batch by batch: each batch fits a
// shader storage block (llvmpipe's holds 128 MiB) and is a multiple of 256 segments, so
// that both ranges keep their offset alignment.
class SegmentBuffers {
 public:
  // `shadows` holds `lights` values a segment.
  SegmentBuffers(const std::vector<GpuSegment>& segments, const std::vector<float>& shadows, size_t lights)
      : count_(segments.size()), lights_(lights) {
    glCreateBuffers(2, buffers_);
    glNamedBufferStorage(buffers_[0], static_cast<GLsizeiptr>(std::max<size_t>(count_, 1) * sizeof(GpuSegment)),
                         segments.empty() ? nullptr : segments.data(), 0);
    glNamedBufferStorage(buffers_[1], static_cast<GLsizeiptr>(std::max<size_t>(shadows.size(), 1) * sizeof(float)),
                         shadows.empty() ? nullptr : shadows.data(), 0);
    GLint block = 0;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    batch_ = std::max<size_t>(
        static_cast<size_t>(block) / std::max(sizeof(GpuSegment), sizeof(float) * lights_) / 256 * 256, 256);
  }
  ~SegmentBuffers() { glDeleteBuffers(2, buffers_); }
  SegmentBuffers(const SegmentBuffers&) = delete;
  SegmentBuffers& operator=(const SegmentBuffers&) = delete;

  void ForEachBatch(const YarnShadowMap::DrawBatch& draw) const {
    for (size_t first = 0; first < count_; first += batch_) {
      const size_t count = std::min(batch_, count_ - first);
      glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, buffers_[0], static_cast<GLintptr>(first * sizeof(GpuSegment)),
                        static_cast<GLsizeiptr>(count * sizeof(GpuSegment)));
      glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, buffers_[1],
                        static_cast<GLintptr>(first * lights_ * sizeof(float)),
                        static_cast<GLsizeiptr>(count * lights_ * sizeof(float)));
      draw(static_cast<GLsizei>(count));
    }
  }

 private:
  size_t count_, lights_, batch_ = 256;
  GLuint buffers_[2] = {0, 0};
};

// A colour texture and a depth texture the yarn pass reads (two framebuffers: the
// opaque pass writes depth, the yarn pass blends into the colour without it).
class LumisliceTarget {
 public:
  LumisliceTarget(int width, int height) : width_(width), height_(height) {
    glCreateTextures(GL_TEXTURE_2D, 1, &colour_);
    glTextureStorage2D(colour_, 1, GL_RGBA32F, width, height);
    glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
    glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, width, height);
    glCreateFramebuffers(1, &opaque_);
    glNamedFramebufferTexture(opaque_, GL_COLOR_ATTACHMENT0, colour_, 0);
    glNamedFramebufferTexture(opaque_, GL_DEPTH_ATTACHMENT, depth_, 0);
    glCreateFramebuffers(1, &yarn_);
    glNamedFramebufferTexture(yarn_, GL_COLOR_ATTACHMENT0, colour_, 0);
    for (const GLuint framebuffer : {opaque_, yarn_}) {
      if (glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw Error(ErrorCode::kInternal, "lumislice renderer: framebuffer incomplete");
      }
    }
  }
  ~LumisliceTarget() {
    glDeleteFramebuffers(1, &opaque_);
    glDeleteFramebuffers(1, &yarn_);
    glDeleteTextures(1, &colour_);
    glDeleteTextures(1, &depth_);
  }
  LumisliceTarget(const LumisliceTarget&) = delete;
  LumisliceTarget& operator=(const LumisliceTarget&) = delete;

  void BindOpaque() const { Bind(opaque_); }
  void BindYarn() const { Bind(yarn_); }
  GLuint depth() const { return depth_; }

  Image ReadPixels() const {
    Image bottom_up(width_, height_, 4);
    glGetTextureImage(colour_, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(bottom_up.pixels.size() * sizeof(float)),
                      bottom_up.pixels.data());
    return FlippedRows(bottom_up);
  }

 private:
  void Bind(GLuint framebuffer) const {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width_, height_);
  }
  int width_, height_;
  GLuint colour_ = 0, depth_ = 0, opaque_ = 0, yarn_ = 0;
};

// How many pixels a length `size` at `position` spans on screen.
struct PixelScale {
  bool orthographic;
  glm::vec3 eye;
  float pixels_per_unit;  // orthographic: per world unit; perspective: per unit at distance 1
  float Pixels(glm::vec3 position, float size) const {
    return orthographic ? size * pixels_per_unit
                        : size * pixels_per_unit / std::max(glm::distance(position, eye), 1e-6f);
  }
};

// The level with the fewest voxels a side that are at least `pixels` (the paper's §5.2.2:
// 2ⁿ ≥ m) and at least kMinLevelResolution; level l has resolution >> l. Coarser levels
// average a section's lit and unlit sides into one colour, which a view of the lit side
// does not see: docs/lumislice.md measures it.
constexpr float kMinLevelResolution = 8.0f;
int LevelFor(float pixels, int resolution, int levels) {
  int level = 0;
  while (level + 1 < levels &&
         static_cast<float>(resolution >> (level + 1)) >= std::max(pixels, kMinLevelResolution)) {
    ++level;
  }
  return level;
}

// Far away a chain's points are closer than a pixel; the segments drawn are at least
// kMinSegmentPixels long: the indices of the points kept (both ends, every change of
// yarn, and the first point at least `min_length(point)` from the last kept).
constexpr float kMinSegmentPixels = 1.0f;
constexpr float kMinYarnPixels = 1.0f;
template <typename MinLength>
std::vector<size_t> KeptPoints(const SkeletonChain& chain, const MinLength& min_length) {
  std::vector<size_t> kept;
  const size_t n = chain.points.size();
  if (n == 0) return kept;
  kept.push_back(0);
  for (size_t i = 1; i < n; ++i) {
    const glm::vec3 last = chain.points[kept.back()];
    if (i + 1 == n || chain.segment_yarn[i] != chain.segment_yarn[i - 1] ||
        glm::distance(chain.points[i], last) >= min_length(last)) {
      kept.push_back(i);
    }
  }
  return kept;
}

// Every knit cloth's yarns: their lumislices in one atlas, and their segments, each at
// its level of detail, in one list (`frame` counts them), in the skeleton's order.
struct CutYarn {
  std::vector<const Lumislice*> atlas_yarns;
  std::vector<SortedSegment> segments;
  std::vector<ShadowSegment> casters;  // the same segments
  int resolution = 0;                  // of the lumislices' finest level
};
CutYarn Cut(const std::vector<SceneMesh>& meshes, const std::vector<const YarnLumislices*>& yarns,
            const PixelScale& scale, glm::vec3 forward, int lod_bias, LumisliceFrame& frame) {
  CutYarn cut;
  uint32_t chains = 0;
  int levels = 0;
  for (size_t m = 0; m < meshes.size() && m < yarns.size(); ++m) {
    if (yarns[m] == nullptr) continue;
    const v1::FabricSpec fabric = WithDefaults(meshes[m].object->fabric().fabric());
    const uint32_t first_yarn = static_cast<uint32_t>(cut.atlas_yarns.size());
    for (const Lumislice& slice : *yarns[m]) {
      if (cut.resolution == 0) {
        cut.resolution = slice.levels.front().resolution;
        levels = static_cast<int>(slice.levels.size());
      }
      if (slice.levels.front().resolution != cut.resolution) {
        throw Error(ErrorCode::kInvalidArgument, "lumislice renderer: every lumislice of a frame needs the same "
                                                 "resolution");
      }
      cut.atlas_yarns.push_back(&slice);
    }
    if (cut.atlas_yarns.size() > kMaxAtlasYarns) {
      throw Error(ErrorCode::kInvalidArgument, "lumislice renderer: at most " + std::to_string(kMaxAtlasYarns) +
                                                   " yarns in a frame's knit cloth");
    }
    const KnitSkeleton skeleton = PlaceKnitSkeleton(
        fabric, meshes[m].mesh, {meshes[m].object->fabric().repeat_u(), meshes[m].object->fabric().repeat_v()});
    for (const SkeletonChain& chain : skeleton.chains) {
      const std::vector<size_t> kept =
          KeptPoints(chain, [&](glm::vec3 p) { return kMinSegmentPixels / scale.Pixels(p, 1.0f); });
      const size_t n = kept.size();
      float arc = 0.0f;
      for (size_t i = 0; i + 1 < n; ++i) {
        const glm::vec3 a = chain.points[kept[i]], b = chain.points[kept[i + 1]];
        const glm::vec3 t = glm::normalize(b - a);
        // The bisectors of the joints (a chain's ends are cut square).
        const glm::vec3 before = i > 0 ? glm::normalize(a - chain.points[kept[i - 1]]) : t;
        const glm::vec3 after = i + 2 < n ? glm::normalize(chain.points[kept[i + 2]] - b) : t;
        const uint32_t yarn = chain.segment_yarn[kept[i]];
        const float radius = 0.5f * (chain.radius[kept[i]] + chain.radius[kept[i + 1]]);
        const Lumislice& slice = (*yarns[m])[yarn];
        const glm::vec3 middle = 0.5f * (a + b);
        // A section narrower than kMinYarnPixels is drawn that wide, its opacity scaled
        // by the part of it the yarn covers.
        const float pixels = scale.Pixels(middle, 2.0f * slice.section.extent() * radius);
        const float widening = std::max(kMinYarnPixels / std::max(pixels, 1e-6f), 1.0f);
        const int level =
            std::clamp(LevelFor(pixels * widening, cut.resolution, levels) + lod_bias, 0, levels - 1);
        SortedSegment sorted;
        sorted.distance =
            scale.orthographic ? glm::dot(middle - scale.eye, forward) : glm::distance(middle, scale.eye);
        sorted.order = cut.segments.size();
        sorted.segment.start = glm::vec4(a, chain.turn[kept[i]]);
        sorted.segment.end = glm::vec4(b, chain.turn[kept[i + 1]]);
        sorted.segment.normal = glm::vec4(chain.normals[kept[i]], radius * widening);
        sorted.segment.start_plane = glm::vec4(glm::normalize(before + t), 0.0f);
        sorted.segment.end_plane = glm::vec4(glm::normalize(t + after), 0.0f);
        sorted.segment.shading = glm::vec4(1.0f / widening, static_cast<float>(level),
                                           static_cast<float>(first_yarn + yarn), 0.0f);
        cut.segments.push_back(sorted);
        cut.casters.push_back({a, b, radius, first_yarn + yarn, chains, arc});
        arc += glm::distance(a, b);
        const float voxel =
            2.0f * slice.section.extent() * radius * widening / static_cast<float>(cut.resolution >> level);
        frame.slices += glm::distance(a, b) / voxel;
        if (frame.segments_per_level.size() <= static_cast<size_t>(level)) {
          frame.segments_per_level.resize(static_cast<size_t>(level) + 1, 0);
        }
        ++frame.segments_per_level[static_cast<size_t>(level)];
      }
      ++chains;
    }
  }
  frame.segments = cut.segments.size();
  return cut;
}

}  // namespace

std::shared_ptr<const YarnLumislices> LumisliceCache::Find(const std::string& key) {
  const auto at = std::find_if(entries_.begin(), entries_.end(), [&](const auto& entry) { return entry.first == key; });
  if (at == entries_.end()) return nullptr;
  entries_.splice(entries_.begin(), entries_, at);
  return entries_.front().second;
}

void LumisliceCache::Insert(const std::string& key, std::shared_ptr<const YarnLumislices> lumislices) {
  entries_.remove_if([&](const auto& entry) { return entry.first == key; });
  entries_.emplace_front(key, std::move(lumislices));
  while (entries_.size() > capacity_) entries_.pop_back();
}

SceneLumislices BuildSceneLumislices(const std::vector<SceneMesh>& meshes, const LumisliceSettings& settings,
                                     LumisliceCache* cache) {
  const Stopwatch stopwatch;
  SceneLumislices built;
  built.per_mesh.assign(meshes.size(), nullptr);
  for (size_t i = 0; i < meshes.size(); ++i) {
    const v1::SceneObject& object = *meshes[i].object;
    if (!object.has_fabric()) continue;
    const v1::FabricSpec fabric = WithDefaults(object.fabric().fabric());
    if (!fabric.has_knit()) {
      throw Error(ErrorCode::kInvalidArgument,
                  "objects[" + std::to_string(i) + "].fabric: lumislice renders knit fabrics only");
    }
    const std::string key = fabric.SerializeAsString();
    auto [at, inserted] = built.by_fabric.try_emplace(key);
    if (inserted) {
      at->second = cache != nullptr ? cache->Find(key) : nullptr;
      if (at->second == nullptr) {
        at->second = std::make_shared<const YarnLumislices>(BuildFabricLumislices(fabric, settings));
        ++built.built;
        if (cache != nullptr) cache->Insert(key, at->second);
      }
    }
    built.per_mesh[i] = at->second.get();
  }
  built.seconds = stopwatch.Seconds();
  return built;
}

LumisliceRenderer::LumisliceRenderer(gl::EglContext& context)
    : context_(context),
      yarn_program_((context.MakeCurrent(), gl::ShaderProgram::FromEmbedded("lumislice.vert", "lumislice.frag"))),
      opaque_program_(gl::ShaderProgram::FromEmbedded("scene.vert", "opaque.frag", "#define LOOM_YARN_SHADOWS\n")) {}

LumisliceRenderer::~LumisliceRenderer() = default;

LumisliceFrame LumisliceRenderer::Render(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes,
                                         const std::vector<const YarnLumislices*>& yarns, uint64_t submission_seed) {
  const Stopwatch stopwatch;
  context_.MakeCurrent();
  const v1::RenderSettings& settings = scene.render();
  // A grid of rays a pixel: the frame that many times larger, averaged at the end.
  const int grid = static_cast<int>(LumisliceRayGrid(settings.msaa_samples()));
  const int width = grid * static_cast<int>(settings.width()), height = grid * static_cast<int>(settings.height());
  const CameraMatrices camera =
      MakeCameraMatrices(scene.camera(), static_cast<float>(width) / static_cast<float>(height));
  const bool orthographic = scene.camera().projection() == v1::PROJECTION_ORTHOGRAPHIC;
  const glm::vec3 forward = glm::normalize(ToGlm(scene.camera().target()) - ToGlm(scene.camera().position()));

  LumisliceFrame frame;
  const PixelScale scale{orthographic, camera.position,
                         orthographic ? static_cast<float>(height) / scene.camera().ortho_height()
                                      : static_cast<float>(height) /
                                            (2.0f * std::tan(glm::radians(scene.camera().fov_y_degrees()) * 0.5f))};
  const int lod_bias = static_cast<int>(std::lround(settings.lod_bias()));
  CutYarn cut = Cut(meshes, yarns, scale, forward, lod_bias, frame);
  const std::vector<const Lumislice*>& atlas_yarns = cut.atlas_yarns;
  std::vector<SortedSegment>& segments = cut.segments;
  const int resolution = cut.resolution;
  // Eq. 10's yarn shadow per segment and light.
  const int light_count = std::min(scene.lights_size(), kMaxLights);
  std::vector<std::vector<float>> yarn_shadows(static_cast<size_t>(light_count));
  YarnShadowProfiles profiles;
  profiles.own_chain_radii = LumisliceSettings().max_light_path;
  for (const Lumislice* slice : atlas_yarns) {
    profiles.profile.push_back(slice->shadow_profile);
    profiles.extent.push_back(slice->section.extent());
  }
  for (int i = 0; i < light_count; ++i) {
    yarn_shadows[static_cast<size_t>(i)] = YarnShadows(cut.casters, profiles, MakeSceneLight(scene.lights(i)));
  }
  if (submission_seed != 0) {
    std::mt19937_64 random(submission_seed);
    std::shuffle(segments.begin(), segments.end(), random);
  }
  // Back to front; ties by the skeleton's order.
  std::sort(segments.begin(), segments.end(), [](const SortedSegment& x, const SortedSegment& y) {
    return x.distance != y.distance ? x.distance > y.distance : x.order < y.order;
  });

  std::vector<GpuSegment> ordered(segments.size());
  const size_t lights = static_cast<size_t>(std::max(light_count, 1));
  std::vector<float> shadows(std::max<size_t>(segments.size() * lights, 1), 1.0f);
  for (size_t k = 0; k < segments.size(); ++k) {
    ordered[k] = segments[k].segment;
    for (int i = 0; i < light_count; ++i) {
      shadows[k * lights + static_cast<size_t>(i)] = yarn_shadows[static_cast<size_t>(i)][segments[k].order];
    }
  }
  const SegmentBuffers segment_buffers(ordered, shadows, lights);

  // Plain objects: opaque, with their macro shadows and the yarn's (eq. 10 in the maps'
  // light views); they cast the only shadow maps.
  std::vector<std::unique_ptr<gl::MeshBuffer>> buffers;
  std::vector<const gl::MeshBuffer*> opaque;
  for (size_t m = 0; m < meshes.size(); ++m) {
    if (m < yarns.size() && yarns[m] != nullptr) continue;
    buffers.push_back(std::make_unique<gl::MeshBuffer>(meshes[m].mesh));
    opaque.push_back(buffers.back().get());
  }
  if (!shadows_ || shadows_->size() != static_cast<int>(settings.shadow_map_size())) {
    shadows_ = std::make_unique<ShadowMaps>(static_cast<int>(settings.shadow_map_size()));
  }
  gl::GpuTimer timer, cloth_timer;
  timer.Start();
  SetUpLights(scene, SceneBoundsOf(meshes), opaque, {}, *shadows_, kYarnShadowUnit + 1,
              {&opaque_program_, &yarn_program_});
  if (!yarn_shadow_map_ || yarn_shadow_map_->size() != shadows_->size()) {
    yarn_shadow_map_ = std::make_unique<YarnShadowMap>(shadows_->size());
  }
  yarn_shadow_map_->Render(*shadows_, atlas_yarns,
                           [&](const YarnShadowMap::DrawBatch& draw) { segment_buffers.ForEachBatch(draw); });

  const LumisliceTarget target(width, height);
  target.BindOpaque();
  const glm::vec3 background = ToGlm(scene.background());
  glClearColor(background.r, background.g, background.b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glBindTextureUnit(kShadowUnit, shadows_->texture());
  glBindTextureUnit(kYarnShadowUnit, yarn_shadow_map_->texture());
  const glm::mat4 view_projection = camera.projection * camera.view;
  opaque_program_.Use();
  opaque_program_.Set("u_shadow_maps", kShadowUnit);
  opaque_program_.Set("u_yarn_shadows", kYarnShadowUnit);
  opaque_program_.Set("u_view_projection", view_projection);
  opaque_program_.Set("u_ambient", ToGlm(scene.ambient()));
  size_t b = 0;
  for (size_t m = 0; m < meshes.size(); ++m) {
    if (m < yarns.size() && yarns[m] != nullptr) continue;
    opaque_program_.Set("u_base_colour", ToGlm(meshes[m].object->base_colour()));
    buffers[b++]->Draw();
  }

  cloth_timer.Start();
  if (!segments.empty()) {
    const LumisliceAtlas atlas(atlas_yarns, resolution);
    target.BindYarn();
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);  // each pixel of a box once, from its back faces
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glBindTextureUnit(kDepthUnit, target.depth());
    atlas.Bind();
    const gl::ShaderProgram& program = yarn_program_;
    program.Use();
    program.Set("u_shadow_maps", kShadowUnit);
    program.Set("u_opaque_depth", kDepthUnit);
    program.Set("u_vrf", kVrfUnit);
    program.Set("u_density", kDensityUnit);
    program.Set("u_view_projection", view_projection);
    program.Set("u_inverse_view_projection", glm::inverse(view_projection));
    program.Set("u_eye", camera.position);
    program.Set("u_orthographic", orthographic ? 1 : 0);
    program.Set("u_view_direction", forward);
    program.Set("u_frame_size", glm::vec2(width, height));
    program.Set("u_resolution", resolution);
    program.Set("u_optical_density", atlas_yarns.front()->optical_density);
    program.Set("u_ambient", ToGlm(scene.ambient()));
    size_t y = 0;
    for (size_t m = 0; m < meshes.size() && m < yarns.size(); ++m) {
      if (yarns[m] == nullptr) continue;
      const v1::FabricSpec fabric = WithDefaults(meshes[m].object->fabric().fabric());
      for (const v1::YarnSpec& spec : fabric.yarns()) {
        const YarnMaterial material = MakeYarnMaterial(spec);
        const int i = static_cast<int>(y);
        program.Set("u_extent", i, atlas_yarns[y]->section.extent());
        program.Set("u_twist_rate", i, atlas_yarns[y]->section.twist_rate);
        program.Set("u_diffuse_albedo", i, material.diffuse_albedo);
        program.Set("u_specular_albedo", i, material.specular_albedo);
        program.Set("u_specular_exponent", i, material.specular_exponent);
        program.Set("u_specular_normalisation", i,
                    KajiyaKayNormalisation(material.specular_exponent));
        ++y;
      }
    }
    GLuint vao = 0, indices = 0;
    glCreateVertexArrays(1, &vao);
    glCreateBuffers(1, &indices);
    glNamedBufferStorage(indices, sizeof(kBoxIndices), kBoxIndices, 0);
    glVertexArrayElementBuffer(vao, indices);
    glBindVertexArray(vao);
    segment_buffers.ForEachBatch(
        [](GLsizei count) { glDrawElementsInstanced(GL_TRIANGLES, 36, GL_UNSIGNED_INT, nullptr, count); });
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &indices);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
  }
  cloth_timer.Stop();
  timer.Stop();
  frame.rendered.image = grid > 1 ? BoxDownsampled(target.ReadPixels(), grid) : target.ReadPixels();
  frame.rendered.gpu_ms = timer.Milliseconds();
  frame.rendered.cloth_gpu_ms = cloth_timer.Milliseconds();
  frame.rendered.cpu_ms = stopwatch.Milliseconds();
  return frame;
}

}  // namespace loom
