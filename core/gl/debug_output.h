#pragma once
// Routes OpenGL debug messages (KHR_debug, core in 4.3) to spdlog, with GL severity
// mapped to log levels. Needs a context created with EGL_CONTEXT_OPENGL_DEBUG.

namespace loom::gl {

// Installs the callback on the current context, synchronous so that a message's
// log line comes from the call that caused it.
void InstallDebugOutput();

}  // namespace loom::gl
