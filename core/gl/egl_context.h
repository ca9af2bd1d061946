#pragma once
// A headless OpenGL 4.5 core context through EGL: no display, no window.
//
// Devices are enumerated with eglQueryDevicesEXT and opened on
// EGL_PLATFORM_DEVICE_EXT, preferring an NVIDIA GPU, then any other hardware
// device, then Mesa's software device (llvmpipe); if none gives a context,
// EGL_PLATFORM_SURFACELESS_MESA is tried. ContextOptions can pin one device. Rendering goes into framebuffer objects
// (core/gl/framebuffer.h); the context has no default framebuffer.

#include <EGL/egl.h>

#include <memory>
#include <string>

namespace loom::gl {

struct DeviceInfo {
  std::string platform;     // "device" or "surfaceless"
  int device_index = -1;    // index in eglQueryDevicesEXT order, -1 for surfaceless
  std::string egl_vendor;   // e.g. "NVIDIA", "Mesa Project"
  std::string gl_vendor;    // GL_VENDOR
  std::string gl_renderer;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string gl_version;   // GL_VERSION
  bool software = false;    // true on llvmpipe and other CPU rasterisers
};

struct ContextOptions {
  // Route GL debug messages to spdlog (core/gl/debug_output.h). On by default in
  // debug builds; LOOM_GL_DEBUG=1 turns it on in any build.
  bool debug = false;
  // Skip hardware devices (for comparisons against llvmpipe on a GPU machine).
  bool software_only = false;
  // Only this EGL device (its index in eglQueryDevicesEXT order, as DeviceInfo and
  // `loom-worker --probe` report it), for one worker per GPU on a machine with
  // several; −1: the best device (see above). An index EGL does not list is
  // Error(kInvalidArgument) naming the devices it does.
  int device_index = -1;
};

ContextOptions DefaultContextOptions();

class EglContext {
 public:
  // Throws Error(kUnavailable) listing what was tried and why each failed.
  static std::unique_ptr<EglContext> Create(const ContextOptions& options = DefaultContextOptions());
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Binds the context to the calling thread.
  void MakeCurrent();
  const DeviceInfo& info() const { return info_; }

 private:
  EglContext(EGLDisplay display, EGLContext context, DeviceInfo info)
      : display_(display), context_(context), info_(std::move(info)) {}

  EGLDisplay display_;
  EGLContext context_;
  DeviceInfo info_;
};

}  // namespace loom::gl
