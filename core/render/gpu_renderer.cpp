#include "core/render/gpu_renderer.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

#include <spdlog/spdlog.h>

#include "core/gl/framebuffer.h"
#include "core/gl/gpu_timer.h"
#include "core/gl/mesh_buffer.h"
#include "core/render/scene_lights.h"
#include "core/scene/camera.h"
#include "core/scene/scene_light.h"
#include "core/spec/defaults.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

// Mesh indices in drawing order: objects without a fabric, then cloth from the
// farthest (bounding-box centre from the eye) to the nearest.
std::vector<size_t> DrawOrder(const std::vector<SceneMesh>& meshes, const std::vector<const GpuFabric*>& fabrics,
                              glm::vec3 eye) {
  std::vector<size_t> opaque, cloth;
  for (size_t i = 0; i < meshes.size(); ++i) (i < fabrics.size() && fabrics[i] ? cloth : opaque).push_back(i);
  std::vector<float> distance(meshes.size());
  for (size_t i : cloth) {
    Bounds bounds;
    bounds.Add(meshes[i].mesh.positions);
    distance[i] = glm::length(bounds.centre() - eye);
  }
  std::stable_sort(cloth.begin(), cloth.end(), [&](size_t a, size_t b) { return distance[a] > distance[b]; });
  opaque.insert(opaque.end(), cloth.begin(), cloth.end());
  return opaque;
}

// Texture units: the shadow maps, then a fabric's textures (GpuFabric::Bind).
// Samplers of different types may not share a unit in a draw, even when a branch
// leaves one unused, so the fabric units are fixed once.
constexpr int kShadowUnit = 0;
constexpr int kFabricUnit = 1;

// Tiles across the object's uv square (t_N).
glm::vec2 FabricRepeat(const v1::SceneObject& object) {
  return {object.fabric().repeat_u(), object.fabric().repeat_v()};
}

// The scene's MSAA sample count, clamped to what this GL can give the float
// target: validation allows up to 16 (a GPU's count), llvmpipe stops at 4, and a
// larger request would leave the framebuffer incomplete.
int MsaaSamples(const v1::RenderSettings& settings) {
  const int requested = static_cast<int>(settings.msaa_samples());
  const int limit = gl::Framebuffer::MaxSamples();
  if (requested <= limit) return requested;
  spdlog::warn("render.msaa_samples {} exceeds this GL's limit of {} samples for a float target; rendering with {}",
               requested, limit, limit);
  return limit;
}

// SHADING_RATE_SAMPLE: cloth shaded once per MSAA sample, each at most at the level
// of its share of the pixel's footprint (half a level finer per doubling of the
// samples; fabric_surface.glsl FabricLevels).
bool SampleShading(const v1::RenderSettings& settings, int samples) {
  return settings.shading_rate() == v1::SHADING_RATE_SAMPLE && samples > 1;
}

float SampleLodBias(const v1::RenderSettings& settings, int samples) {
  return SampleShading(settings, samples) ? -0.5f * std::log2(static_cast<float>(samples)) : 0.0f;
}

void SetSampleShading(bool on) {
  if (on) {
    glEnable(GL_SAMPLE_SHADING);
    glMinSampleShading(1.0f);
  } else {
    glDisable(GL_SAMPLE_SHADING);
  }
}

// Where cloth is shaded (render.shading_pass): the compute pass only when asked,
// and not shaded per sample (the G-buffer holds one sample a pixel). The fragment
// pass measured faster on both GPUs measured, llvmpipe and an NVIDIA H200
// (docs/gpu.md, "Where cloth is shaded").
bool UsesComputePass(const v1::RenderSettings& settings, int samples) {
  return settings.shading_pass() == v1::SHADING_PASS_COMPUTE && !SampleShading(settings, samples);
}

// The defines of each cloth program of the compute pass (core/shaders/cloth.glsl).
const char* PassDefines(ClothPass pass) {
  switch (pass) {
    case ClothPass::kGbuffer:
      return "#define LOOM_CLOTH_GBUFFER\n";
    case ClothPass::kCompute:
      return "#define LOOM_CLOTH_COMPUTE\n";
    case ClothPass::kComposite:
      return "#define LOOM_CLOTH_COMPOSITE\n";
    default:
      return "";
  }
}

gl::ShaderProgram OpaqueProgram() {
  gl::ShaderProgram program = gl::ShaderProgram::FromEmbedded("scene.vert", "opaque.frag");
  program.Set("u_shadow_maps", kShadowUnit);
  return program;
}

}  // namespace

GpuRenderer::GpuRenderer(gl::EglContext& context)
    : context_(context), opaque_program_((context.MakeCurrent(), OpaqueProgram())) {}

gl::ShaderProgram& GpuRenderer::ClothProgramFor(const GpuFabric& fabric, const v1::RenderSettings& settings,
                                                ClothPass pass) {
  const FabricMethod& method = fabric.method();
  std::string defines = fabric.ShaderDefines() + PassDefines(pass);
  if (settings.level_mode() == v1::LEVEL_MODE_ANISOTROPIC) defines += "#define LOOM_ANISOTROPIC_LEVELS\n";
  if (settings.texel_filter() == v1::TEXEL_FILTER_BILINEAR) defines += "#define LOOM_BILINEAR_TEXELS\n";
  if (fabric.colour_channels()) defines += "#define LOOM_COLOUR_SHEET\n";
  const std::string key = std::string(method.cloth_shader()) + "\n" + defines;
  auto found = cloth_programs_.find(key);
  if (found == cloth_programs_.end()) {
    gl::ShaderProgram program =
        pass == ClothPass::kCompute ? gl::ShaderProgram::ComputeFromEmbedded(method.cloth_shader(), defines)
                                    : gl::ShaderProgram::FromEmbedded("scene.vert", method.cloth_shader(), defines);
    program.Set("u_shadow_maps", kShadowUnit);
    found = cloth_programs_.emplace(key, std::move(program)).first;
  }
  return found->second;
}

RenderedFrame GpuRenderer::Render(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes,
                                  const std::vector<const GpuFabric*>& fabrics) {
  const Stopwatch stopwatch;
  context_.MakeCurrent();
  const v1::RenderSettings& settings = scene.render();
  const int width = static_cast<int>(settings.width()), height = static_cast<int>(settings.height());
  const int samples = MsaaSamples(settings);
  const bool per_sample = SampleShading(settings, samples);
  const bool compute = UsesComputePass(settings, samples);
  // Each cloth object's draws, one per sheet of its asset, and every program of the
  // frame once.
  std::vector<std::vector<SheetDraw>> cloth(meshes.size());
  std::vector<const gl::ShaderProgram*> programs = {&opaque_program_};
  const auto add = [&programs](const gl::ShaderProgram* program) {
    if (program != nullptr && std::find(programs.begin(), programs.end(), program) == programs.end()) {
      programs.push_back(program);
    }
  };
  const auto programs_of = [&](const GpuFabric& fabric) {
    ClothPrograms of;
    if (compute) {
      of.gbuffer = &ClothProgramFor(fabric, settings, ClothPass::kGbuffer);
      of.compute = &ClothProgramFor(fabric, settings, ClothPass::kCompute);
      of.shade = &ClothProgramFor(fabric, settings, ClothPass::kComposite);
    } else {
      of.shade = &ClothProgramFor(fabric, settings, ClothPass::kShade);
    }
    for (const gl::ShaderProgram* program : {of.shade, of.gbuffer, of.compute}) add(program);
    return of;
  };
  for (size_t i = 0; i < meshes.size() && i < fabrics.size(); ++i) {
    if (fabrics[i] == nullptr) continue;
    const v1::FabricSpec fabric = WithDefaults(meshes[i].object->fabric().fabric());
    const auto add_sheet = [&](const GpuFabric& sheet) {
      const glm::mat3 colours =
          sheet.colour_channels() ? SheetColours(fabric, *sheet.colour_channels()) : glm::mat3(1.0f);
      cloth[i].push_back({&sheet, programs_of(sheet), false, colours});
      if (sheet.back() != nullptr) cloth[i].push_back({sheet.back(), programs_of(*sheet.back()), true, colours});
    };
    add_sheet(*fabrics[i]);
    for (const auto& sheet : fabrics[i]->colour_sheets()) add_sheet(*sheet);
  }
  const auto cloth_programs = std::span(programs).subspan(1);
  if (!shadows_ || shadows_->size() != static_cast<int>(settings.shadow_map_size())) {
    shadows_ = std::make_unique<ShadowMaps>(static_cast<int>(settings.shadow_map_size()));
  }

  std::vector<std::unique_ptr<gl::MeshBuffer>> buffers;
  std::vector<const gl::MeshBuffer*> opaque_casters;
  std::vector<ShadowMaps::ClothCaster> cloth_casters;
  for (size_t i = 0; i < meshes.size(); ++i) {
    buffers.push_back(std::make_unique<gl::MeshBuffer>(meshes[i].mesh));
    const GpuFabric* fabric = i < fabrics.size() ? fabrics[i] : nullptr;
    if (fabric == nullptr) {
      opaque_casters.push_back(buffers.back().get());
    } else {
      cloth_casters.push_back({buffers.back().get(), fabric, FabricRepeat(*meshes[i].object)});
    }
  }

  gl::GpuTimer timer, shadow_timer, cloth_timer;
  timer.Start();
  shadow_timer.Start();
  SetUpLights(scene, SceneBoundsOf(meshes), opaque_casters, cloth_casters, *shadows_, kFabricUnit, programs);
  shadow_timer.Stop();

  if (compute && (!gbuffer_ || gbuffer_->width() != width || gbuffer_->height() != height)) {
    gbuffer_.reset();
    gbuffer_ = std::make_unique<ClothGbuffer>(width, height);
  }
  if (compute) gbuffer_->ResetCounter();
  if (!target_ || target_->width() != width || target_->height() != height || target_->samples() != samples) {
    target_.reset();  // before the new one: at 1080p with 4× MSAA it holds about 200 MB
    target_ = std::make_unique<gl::Framebuffer>(width, height, samples);
  }
  target_->Bind();
  const glm::vec3 background = ToGlm(scene.background());
  glClearColor(background.r, background.g, background.b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);  // cloth is seen from both sides

  const CameraMatrices camera =
      MakeCameraMatrices(scene.camera(), static_cast<float>(width) / static_cast<float>(height));
  for (const gl::ShaderProgram* program : programs) {
    program->Set("u_view_projection", camera.projection * camera.view);
    program->Set("u_ambient", ToGlm(scene.ambient()));
  }
  for (const gl::ShaderProgram* program : cloth_programs) {
    program->Set("u_eye", camera.position);
    program->Set("u_orthographic", scene.camera().projection() == v1::PROJECTION_ORTHOGRAPHIC ? 1 : 0);
    program->Set("u_towards_viewer", glm::normalize(camera.position - ToGlm(scene.camera().target())));
    program->Set("u_level_mode", static_cast<int>(settings.level_mode()));
    program->Set("u_lod_bias", settings.lod_bias());
    program->Set("u_sample_lod_bias", SampleLodBias(settings, samples));
  }
  glBindTextureUnit(kShadowUnit, shadows_->texture());
  // Opaque objects first, then cloth back to front with premultiplied blending:
  // a fabric's alpha is the fraction of the pixel its yarns cover (holes let what
  // lies behind show through), exact for one layer of cloth over anything opaque.
  // Only a cloth seen through its own holes (a fold) depends on triangle order.
  // A cloth with further sheets is drawn again at once with each, adding its light
  // where the first was drawn (equal depth): a back sheet's from behind the surface
  // (no ambient twice), a colour sheet's from its components; each sheet's channels
  // mapped to RGB by its colours (identity but for colour components).
  const auto draw_cloth = [&](size_t i, const GpuFabric& fabric, const ClothPrograms& of) {
    const glm::vec2 repeat = FabricRepeat(*meshes[i].object);
    if (of.compute != nullptr) ShadeInComputePass(*buffers[i], fabric, repeat, of);
    of.shade->Use();
    fabric.Bind(*of.shade, kFabricUnit, repeat);
    buffers[i]->Draw();
  };
  bool cloth_started = false;
  for (const size_t i : DrawOrder(meshes, fabrics, camera.position)) {
    const v1::SceneObject& object = *meshes[i].object;
    const GpuFabric* fabric = i < fabrics.size() ? fabrics[i] : nullptr;
    if (fabric == nullptr) {
      SetSampleShading(false);
      opaque_program_.Use();
      opaque_program_.Set("u_base_colour", ToGlm(object.base_colour()));
      buffers[i]->Draw();
      continue;
    }
    if (!cloth_started) cloth_timer.Start();
    cloth_started = true;
    SetSampleShading(per_sample);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    for (size_t k = 0; k < cloth[i].size(); ++k) {
      // Programs are shared between sheets (the same method and defines): set per draw.
      const SheetDraw& sheet = cloth[i][k];
      for (const gl::ShaderProgram* program : {sheet.programs.shade, sheet.programs.compute}) {
        if (program == nullptr) continue;
        program->Set("u_back_sheet", sheet.back ? 1 : 0);
        program->Set("u_ambient", sheet.back ? glm::vec3(0.0f) : ToGlm(scene.ambient()));
        program->Set("u_colour_mix", sheet.colours);
      }
      if (k == 1) {
        glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ZERO, GL_ONE);
        glDepthFunc(GL_EQUAL);
        glDepthMask(GL_FALSE);
      }
      draw_cloth(i, *sheet.fabric, sheet.programs);
    }
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
  }
  if (!cloth_started) cloth_timer.Start();
  glDisable(GL_BLEND);
  SetSampleShading(false);
  cloth_timer.Stop();
  timer.Stop();

  RenderedFrame frame;
  frame.image = target_->ReadPixels();
  frame.gpu_ms = timer.Milliseconds();
  frame.shadow_gpu_ms = shadow_timer.Milliseconds();
  frame.cloth_gpu_ms = cloth_timer.Milliseconds();
  frame.compute_pass = compute;
  if (compute) frame.shaded_in_place = gbuffer_->Counter();
  frame.cpu_ms = stopwatch.Milliseconds();
  return frame;
}

// The compute pass's first passes over one cloth: the G-buffers of its two nearest
// layers, then their shadings; the composite (programs.shade) then draws the cloth
// with them.
// Leaves the frame's target bound, with its depth test and blending as they were.
void GpuRenderer::ShadeInComputePass(const gl::MeshBuffer& mesh, const GpuFabric& fabric, glm::vec2 repeat,
                                     const ClothPrograms& programs) {
  GLboolean blend = GL_FALSE, depth_mask = GL_TRUE;
  GLint depth_func = GL_LESS;
  glGetBooleanv(GL_BLEND, &blend);
  glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask);
  glGetIntegerv(GL_DEPTH_FUNC, &depth_func);
  // What the last composite read of the images is done before they are written again.
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  glDisable(GL_BLEND);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  programs.gbuffer->Use();
  fabric.Bind(*programs.gbuffer, kFabricUnit, repeat);
  for (int layer = 0; layer < ClothGbuffer::kLayers; ++layer) {
    gbuffer_->BindAndClear(layer);
    programs.gbuffer->Set("u_peel", layer > 0 ? 1 : 0);
    mesh.Draw();
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
  }
  programs.compute->Use();
  fabric.Bind(*programs.compute, kFabricUnit, repeat);
  for (int layer = 0; layer < ClothGbuffer::kLayers; ++layer) {
    gbuffer_->BindForCompute(layer);
    gbuffer_->Dispatch();
  }
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT);
  gbuffer_->BindForComposite();
  target_->Bind();
  if (blend) glEnable(GL_BLEND);
  glDepthFunc(static_cast<GLenum>(depth_func));
  glDepthMask(depth_mask);
}

}  // namespace loom
