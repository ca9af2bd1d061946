#pragma once
// Shader sources compiled into the binary from core/shaders/ (cmake/EmbedShaders.cmake).

#include <span>
#include <string_view>

namespace loom::gl {

struct ShaderSource {
  std::string_view name;  // file name, e.g. "test_scene.frag"
  std::string_view text;
};

std::span<const ShaderSource> EmbeddedShaders();

}  // namespace loom::gl
