#include "tests/core/gl/fullscreen_pass.h"

#include "core/gl/framebuffer.h"
#include "core/gl/shader_program.h"

namespace loom::gl {

Image RunFullscreenPass(const std::string& fragment, int width, int height) {
  // One triangle that covers the viewport, from gl_VertexID alone.
  static constexpr const char* kVertex = R"(#version 450 core
void main() {
  vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)";
  Framebuffer target(width, height);
  ShaderProgram program =
      ShaderProgram::Link({{GL_VERTEX_SHADER, "fullscreen.vert", kVertex}, {GL_FRAGMENT_SHADER, "pass.frag", fragment}});
  GLuint empty_vao = 0;
  glCreateVertexArrays(1, &empty_vao);  // core profile draws need a bound VAO
  target.Bind();
  glDisable(GL_DEPTH_TEST);
  program.Use();
  glBindVertexArray(empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDeleteVertexArrays(1, &empty_vao);
  return target.ReadPixels();
}

}  // namespace loom::gl
