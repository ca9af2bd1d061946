#pragma once
// A linked GLSL program. Compile and link errors throw Error(kInternal) with every
// driver message rewritten as "<file>:<line>: <message>", so a broken shader names
// its own file and line on Mesa and NVIDIA alike.

#include <GL/glcorearb.h>

#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace loom::gl {

struct ShaderStage {
  GLenum type;       // GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, ...
  std::string name;  // file name used in error messages
  std::string text;
};

class ShaderProgram {
 public:
  static ShaderProgram Link(const std::vector<ShaderStage>& stages);
  // Links the embedded vertex and fragment shaders of these file names, each with
  // `defines` ("#define NAME\n" lines) after its #version line: a variant compiled
  // apart, so that code one variant needs costs the other nothing.
  static ShaderProgram FromEmbedded(std::string_view vertex_file, std::string_view fragment_file,
                                    std::string_view defines = {});
  // "<base>.vert" and "<base>.frag".
  static ShaderProgram FromEmbedded(std::string_view base);
  // The embedded file compiled as a compute shader, with `defines` as above.
  static ShaderProgram ComputeFromEmbedded(std::string_view file, std::string_view defines = {});

  ShaderProgram(ShaderProgram&& other) noexcept : program_(other.program_) { other.program_ = 0; }
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;
  ~ShaderProgram();

  void Use() const { glUseProgram(program_); }
  GLuint id() const { return program_; }

  // Setters for the current program; an unknown (or optimised-away) uniform is ignored.
  void Set(const char* name, float value) const;
  void Set(const char* name, int value) const;
  void Set(const char* name, const glm::vec2& value) const;
  void Set(const char* name, const glm::vec3& value) const;
  void Set(const char* name, const glm::vec4& value) const;
  void Set(const char* name, const glm::mat3& value) const;
  void Set(const char* name, const glm::mat4& value) const;
  // Element `index` of the uniform array `name`.
  template <typename T>
  void Set(const char* name, int index, const T& value) const {
    Set((std::string(name) + "[" + std::to_string(index) + "]").c_str(), value);
  }

 private:
  explicit ShaderProgram(GLuint program) : program_(program) {}
  GLuint program_ = 0;
};

// A stage's text with every `#include "name.glsl"` line replaced by that embedded
// shader (recursively, each file once), and `#line` directives so that the driver
// numbers each file's lines from 1 under its own source-string number:
// files[n] is the file of source string n (files[0] is the stage itself).
struct ExpandedSource {
  std::string text;
  std::vector<std::string> files;
};
ExpandedSource ExpandIncludes(const std::string& name, const std::string& text);

// Rewrites a driver info log so each line reads "<file>:<line>: <message>", the
// file found by source-string number in `files`. Understands Mesa
// ("0:12(5): error: ...") and NVIDIA ("0(12) : error C0000: ...").
std::string AnnotateShaderLog(std::string_view log, const std::vector<std::string>& files);

}  // namespace loom::gl
