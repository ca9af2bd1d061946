#include "core/render/test_scene.h"

#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "core/gl/framebuffer.h"
#include "core/gl/mesh_buffer.h"
#include "core/gl/shader_program.h"
#include "core/scene/builtin_shapes.h"
#include "core/util/error.h"

namespace loom {

Image RenderTestScene(gl::EglContext& context, const TestSceneOptions& options) {
  context.MakeCurrent();
  // A smoke test renders what it is asked or says why not (the svbrdf renderer clamps instead).
  const int max_samples = gl::Framebuffer::MaxSamples();
  if (options.msaa_samples > max_samples) {
    throw Error(ErrorCode::kInvalidArgument,
                "msaa_samples " + std::to_string(options.msaa_samples) + " exceeds this GL's limit of " +
                    std::to_string(max_samples) + " samples for a float framebuffer");
  }
  gl::Framebuffer target(options.width, options.height, options.msaa_samples);
  gl::ShaderProgram program = gl::ShaderProgram::FromEmbedded("test_scene");
  gl::MeshBuffer floor(MakePlane(1));
  gl::MeshBuffer sphere(MakeSphere(48));

  const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height);
  const glm::vec3 eye(2.4f, -3.2f, 2.0f);
  const glm::mat4 view = glm::lookAt(eye, glm::vec3(0.0f, 0.0f, 0.5f), glm::vec3(0.0f, 0.0f, 1.0f));
  const glm::mat4 projection = glm::perspective(glm::radians(40.0f), aspect, 0.1f, 50.0f);

  target.Bind();
  glEnable(GL_DEPTH_TEST);
  glClearColor(0.02f, 0.025f, 0.03f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  program.Use();
  program.Set("u_view_projection", projection * view);
  program.Set("u_eye", eye);
  program.Set("u_light_direction", glm::normalize(glm::vec3(-0.4f, -0.6f, 1.0f)));
  program.Set("u_light_radiance", glm::vec3(3.0f));
  program.Set("u_ambient", glm::vec3(0.08f, 0.09f, 0.11f));

  // Floor: 6 x 6 units, 12 checks across.
  program.Set("u_model", glm::scale(glm::mat4(1.0f), glm::vec3(6.0f, 6.0f, 1.0f)));
  program.Set("u_pattern_scale", glm::vec4(12.0f, 12.0f, 0.0f, 0.0f));
  program.Set("u_colour_a", glm::vec3(0.70f, 0.68f, 0.62f));
  program.Set("u_colour_b", glm::vec3(0.25f, 0.24f, 0.22f));
  floor.Draw();

  // Sphere resting on the floor, 16 stripes around.
  program.Set("u_model", glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 1.0f)));
  program.Set("u_pattern_scale", glm::vec4(16.0f, 0.0f, 0.0f, 0.0f));
  program.Set("u_colour_a", glm::vec3(0.65f, 0.08f, 0.06f));
  program.Set("u_colour_b", glm::vec3(0.85f, 0.72f, 0.20f));
  sphere.Draw();

  return target.ReadPixels();
}

}  // namespace loom
