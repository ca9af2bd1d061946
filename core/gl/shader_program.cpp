#include "core/gl/shader_program.h"

#include <glm/gtc/type_ptr.hpp>
#include <algorithm>
#include <cstring>
#include <regex>
#include <sstream>

#include "core/gl/shader_sources.h"
#include "core/util/error.h"

namespace loom::gl {
namespace {

std::string InfoLog(GLuint object, bool is_program) {
  GLint length = 0;
  if (is_program) glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
  else glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  if (is_program) glGetProgramInfoLog(object, length, nullptr, log.data());
  else glGetShaderInfoLog(object, length, nullptr, log.data());
  log.resize(std::strlen(log.c_str()));
  return log;
}

GLuint Compile(const ShaderStage& stage) {
  const ExpandedSource source = ExpandIncludes(stage.name, stage.text);
  const GLuint shader = glCreateShader(stage.type);
  const char* text = source.text.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = InfoLog(shader, false);
    glDeleteShader(shader);
    throw Error(ErrorCode::kInternal, "shader " + stage.name + " failed to compile:\n" +
                                          AnnotateShaderLog(log, source.files));
  }
  return shader;
}

std::string_view FindEmbedded(const std::string& name) {
  for (const ShaderSource& source : EmbeddedShaders()) {
    if (source.name == name) return source.text;
  }
  throw Error(ErrorCode::kInternal, "no embedded shader named " + name + " (is it in core/shaders/?)");
}

}  // namespace

namespace {

// Appends `text` (from `file`, source string number `number`) to `out`, expanding
// includes depth-first. `#line` keeps each file's own numbering; the #version
// line must stay first, so a stage's own text starts being numbered after it.
void Expand(const std::string& file, const std::string& text, ExpandedSource& out) {
  static const std::regex kInclude(R"re(^\s*#\s*include\s+"([^"]+)"\s*$)re");
  const int number = static_cast<int>(out.files.size());
  out.files.push_back(file);
  std::istringstream lines(text);
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    std::smatch match;
    if (std::regex_match(line, match, kInclude)) {
      const std::string included = match[1].str();
      if (std::find(out.files.begin(), out.files.end(), included) == out.files.end()) {
        out.text += "#line 1 " + std::to_string(out.files.size()) + "\n";
        Expand(included, std::string(FindEmbedded(included)), out);
      }
      out.text += "#line " + std::to_string(line_number + 1) + " " + std::to_string(number) + "\n";
    } else {
      out.text += line + "\n";
    }
  }
}

}  // namespace

ExpandedSource ExpandIncludes(const std::string& name, const std::string& text) {
  ExpandedSource expanded;
  Expand(name, text, expanded);
  return expanded;
}

std::string AnnotateShaderLog(std::string_view log, const std::vector<std::string>& files) {
  // Mesa: "0:12(5): error: ..."; NVIDIA: "0(12) : error C0000: ...".
  static const std::regex kMesa(R"(^\s*(\d+):(\d+)\(\d+\):\s*(.*)$)");
  static const std::regex kNvidia(R"(^\s*(\d+)\((\d+)\)\s*:\s*(.*)$)");
  const auto file_of = [&files](const std::string& number) {
    const size_t index = std::stoul(number);
    return index < files.size() ? files[index] : "source " + number;
  };
  std::istringstream lines{std::string(log)};
  std::string line, annotated;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    std::smatch match;
    if (std::regex_match(line, match, kMesa) || std::regex_match(line, match, kNvidia)) {
      annotated += file_of(match[1].str()) + ":" + match[2].str() + ": " + match[3].str() + "\n";
    } else {
      annotated += (files.empty() ? std::string("shader") : files[0]) + ": " + line + "\n";
    }
  }
  return annotated;
}

ShaderProgram ShaderProgram::Link(const std::vector<ShaderStage>& stages) {
  std::vector<GLuint> shaders;
  try {
    for (const ShaderStage& stage : stages) shaders.push_back(Compile(stage));
  } catch (...) {
    for (GLuint shader : shaders) glDeleteShader(shader);
    throw;
  }
  const GLuint program = glCreateProgram();
  for (GLuint shader : shaders) glAttachShader(program, shader);
  glLinkProgram(program);
  for (GLuint shader : shaders) glDeleteShader(shader);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::string names;
    for (const ShaderStage& stage : stages) names += (names.empty() ? "" : " + ") + stage.name;
    const std::string log = InfoLog(program, true);
    glDeleteProgram(program);
    throw Error(ErrorCode::kInternal, "shader program " + names + " failed to link:\n" + log);
  }
  return ShaderProgram(program);
}

namespace {

// `text` with `defines` after its #version line, which must come first; #line keeps
// the file's numbering.
std::string WithDefines(std::string_view text, std::string_view defines) {
  std::string out(text);
  if (defines.empty()) return out;
  const size_t first_line = out.find('\n');
  if (first_line == std::string::npos) throw Error(ErrorCode::kInternal, "shader without a #version line");
  out.insert(first_line + 1, std::string(defines) + "#line 2 0\n");
  return out;
}

}  // namespace

ShaderProgram ShaderProgram::FromEmbedded(std::string_view vertex_file, std::string_view fragment_file,
                                          std::string_view defines) {
  const std::string vertex(vertex_file), fragment(fragment_file);
  return Link({{GL_VERTEX_SHADER, vertex, WithDefines(FindEmbedded(vertex), defines)},
               {GL_FRAGMENT_SHADER, fragment, WithDefines(FindEmbedded(fragment), defines)}});
}

ShaderProgram ShaderProgram::ComputeFromEmbedded(std::string_view file, std::string_view defines) {
  const std::string name(file);
  return Link({{GL_COMPUTE_SHADER, name, WithDefines(FindEmbedded(name), defines)}});
}

ShaderProgram ShaderProgram::FromEmbedded(std::string_view base) {
  return FromEmbedded(std::string(base) + ".vert", std::string(base) + ".frag");
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (program_ != 0) glDeleteProgram(program_);
    program_ = other.program_;
    other.program_ = 0;
  }
  return *this;
}

ShaderProgram::~ShaderProgram() {
  if (program_ != 0) glDeleteProgram(program_);
}

void ShaderProgram::Set(const char* name, float value) const {
  glProgramUniform1f(program_, glGetUniformLocation(program_, name), value);
}
void ShaderProgram::Set(const char* name, int value) const {
  glProgramUniform1i(program_, glGetUniformLocation(program_, name), value);
}
void ShaderProgram::Set(const char* name, const glm::vec2& value) const {
  glProgramUniform2fv(program_, glGetUniformLocation(program_, name), 1, glm::value_ptr(value));
}
void ShaderProgram::Set(const char* name, const glm::vec3& value) const {
  glProgramUniform3fv(program_, glGetUniformLocation(program_, name), 1, glm::value_ptr(value));
}
void ShaderProgram::Set(const char* name, const glm::vec4& value) const {
  glProgramUniform4fv(program_, glGetUniformLocation(program_, name), 1, glm::value_ptr(value));
}
void ShaderProgram::Set(const char* name, const glm::mat3& value) const {
  glProgramUniformMatrix3fv(program_, glGetUniformLocation(program_, name), 1, GL_FALSE, glm::value_ptr(value));
}
void ShaderProgram::Set(const char* name, const glm::mat4& value) const {
  glProgramUniformMatrix4fv(program_, glGetUniformLocation(program_, name), 1, GL_FALSE, glm::value_ptr(value));
}

}  // namespace loom::gl
