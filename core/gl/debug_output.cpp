#include "core/gl/debug_output.h"

#include <GL/glcorearb.h>
#include <spdlog/spdlog.h>

#include <string_view>

namespace loom::gl {
namespace {

const char* SourceName(GLenum source) {
  switch (source) {
    case GL_DEBUG_SOURCE_API: return "api";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM: return "window-system";
    case GL_DEBUG_SOURCE_SHADER_COMPILER: return "shader-compiler";
    case GL_DEBUG_SOURCE_THIRD_PARTY: return "third-party";
    case GL_DEBUG_SOURCE_APPLICATION: return "application";
    default: return "other";
  }
}

const char* TypeName(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined-behaviour";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
    default: return "other";
  }
}

spdlog::level::level_enum Level(GLenum type, GLenum severity) {
  if (type == GL_DEBUG_TYPE_ERROR) return spdlog::level::err;
  switch (severity) {
    case GL_DEBUG_SEVERITY_HIGH: return spdlog::level::err;
    case GL_DEBUG_SEVERITY_MEDIUM: return spdlog::level::warn;
    case GL_DEBUG_SEVERITY_LOW: return spdlog::level::info;
    default: return spdlog::level::debug;  // notifications
  }
}

void APIENTRY OnDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                               const GLchar* message, const void* /*user*/) {
  const std::string_view text = length >= 0 ? std::string_view(message, static_cast<size_t>(length))
                                            : std::string_view(message);
  spdlog::log(Level(type, severity), "GL {} {} #{}: {}", SourceName(source), TypeName(type), id, text);
}

}  // namespace

void InstallDebugOutput() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(OnDebugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

}  // namespace loom::gl
