#pragma once
// The GPU frame renderer (DESIGN.md "Renderers"; render method RENDER_METHOD_SVBRDF):
// rasterises a scene with OpenGL 4.5 core through EGL — the same code on an NVIDIA
// GPU and on llvmpipe — with macro-scale shadow maps and MSAA. Cloth is shaded by its
// fabric's method (core/methods/fabric_method.h: the method's cloth program,
// core/shaders/cloth.glsl), per fragment or, with render.shading_pass COMPUTE, in a
// compute pass over G-buffers (ClothGbuffer); a cloth with a back sheet
// (FabricAsset::back) is drawn again with it for the light from behind. Objects
// without a fabric are Lambertian in their base colour (opaque.frag), a program of
// their own.
//
// Light units: a directional light's colour × intensity is the irradiance it brings
// at normal incidence; a point light's is its intensity (irradiance = I / d²);
// ambient is the radiance of a uniform, unshadowed environment.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/gl/egl_context.h"
#include "core/gl/framebuffer.h"
#include "core/gl/shader_program.h"
#include "core/gl/mesh_buffer.h"
#include "core/image/image.h"
#include "core/methods/fabric_method.h"
#include "core/render/cloth_gbuffer.h"
#include "core/render/shadow_maps.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/scene.pb.h"

namespace loom {

struct RenderedFrame {
  Image image;          // linear radiance, RGBA (alpha 1)
  double cpu_ms = 0.0;  // wall time of Render, upload and read-back included
  double gpu_ms = 0.0;  // GPU time of the shadow and main passes (GL timestamps)
  double shadow_gpu_ms = 0.0;  // of which the shadow maps
  double cloth_gpu_ms = 0.0;   // of which the cloth, every pass of it
  bool compute_pass = false;   // cloth shaded in the compute pass (render.shading_pass)
  // The compute pass: fragments its composite shaded in place, for want of their
  // pixel in the G-buffer (core/shaders/cloth.glsl).
  uint64_t shaded_in_place = 0;
};

// The programs a cloth is drawn with (core/shaders/cloth.glsl): `shade` draws it
// into the frame, by itself in the fragment pass or as the composite of the
// compute pass, which first fills the G-buffer with `gbuffer` and shades its pixels
// with `compute` (both null in the fragment pass).
enum class ClothPass { kShade, kGbuffer, kCompute, kComposite };
struct ClothPrograms {
  const gl::ShaderProgram* shade = nullptr;
  const gl::ShaderProgram* gbuffer = nullptr;
  const gl::ShaderProgram* compute = nullptr;
};

// One draw of a cloth: a sheet of its asset (GpuFabric: the asset, a colour sheet, or
// either's back sheet), its programs, and the matrix from its channels to RGB
// (core/methods/colour_sheets.h SheetColours).
struct SheetDraw {
  const GpuFabric* fabric = nullptr;
  ClothPrograms programs;
  bool back = false;
  glm::mat3 colours{1.0f};
};

class GpuRenderer {
 public:
  // Compiles the programs once; a worker keeps one renderer for every frame.
  explicit GpuRenderer(gl::EglContext& context);

  // `scene` with defaults applied and validated; `meshes` = BuildSceneGeometry(scene);
  // `fabrics[i]` the fabric of meshes[i] on this context's GPU, or null for a plain
  // object; objects may differ in method.
  RenderedFrame Render(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes,
                       const std::vector<const GpuFabric*>& fabrics);

 private:
  // The cloth program of `fabric`'s method, with the fabric's own defines, for the
  // scene's level mode and texel filter.
  // Anisotropic levels and bilinear texels are compiles of their own
  // (core/shaders/cloth.glsl: llvmpipe runs both sides of a branch, even on a
  // uniform), each made the first time a scene asks for it, keyed by its shader and
  // defines.
  gl::ShaderProgram& ClothProgramFor(const GpuFabric& fabric, const v1::RenderSettings& settings, ClothPass pass);
  void ShadeInComputePass(const gl::MeshBuffer& mesh, const GpuFabric& fabric, glm::vec2 repeat,
                          const ClothPrograms& programs);

  gl::EglContext& context_;
  std::map<std::string, gl::ShaderProgram> cloth_programs_;  // by shader and defines
  gl::ShaderProgram opaque_program_;  // objects without a fabric (core/shaders/opaque.frag)
  // Kept from frame to frame while the size and sample count stay: allocating the
  // multisampled float target each frame is a large share of llvmpipe's frame
  // (docs/gpu.md, "llvmpipe frame time").
  std::unique_ptr<gl::Framebuffer> target_;
  std::unique_ptr<ShadowMaps> shadows_;
  std::unique_ptr<ClothGbuffer> gbuffer_;  // the compute pass's, kept alike
};

}  // namespace loom
