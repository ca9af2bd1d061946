#pragma once
// The GL test scene: a striped sphere resting on a checkered floor under a
// directional light, rendered with Lambert + Blinn-Phong shading into a float
// framebuffer. It exercises the whole headless path (EGL context, shaders from
// core/shaders/, meshes with UVs, depth, MSAA, float read-back) before the fabric
// renderers exist, and stays as the smoke test of a new machine's GL stack.

#include "core/gl/egl_context.h"
#include "core/image/image.h"

namespace loom {

struct TestSceneOptions {
  int width = 640;
  int height = 480;
  int msaa_samples = 4;
};

// Linear radiance, RGBA. Needs `context` current on this thread. Throws
// Error(kInvalidArgument) if msaa_samples exceeds gl::Framebuffer::MaxSamples().
Image RenderTestScene(gl::EglContext& context, const TestSceneOptions& options);

}  // namespace loom
