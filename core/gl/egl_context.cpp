#include "core/gl/egl_context.h"

#include <EGL/eglext.h>
#include <GL/glcorearb.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/gl/debug_output.h"
#include "core/util/error.h"

namespace loom::gl {
namespace {

// Not in older EGL headers.
#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif

std::string EglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: break;
  }
  char hex[32];
  std::snprintf(hex, sizeof hex, "EGL error 0x%x", static_cast<unsigned>(error));
  return hex;
}

bool HasExtension(const char* extensions, const char* name) {
  if (extensions == nullptr) return false;
  const size_t length = std::strlen(name);
  for (const char* p = extensions; (p = std::strstr(p, name)) != nullptr; p += length) {
    const bool starts = p == extensions || p[-1] == ' ';
    const bool ends = p[length] == ' ' || p[length] == '\0';
    if (starts && ends) return true;
  }
  return false;
}

template <typename Proc>
Proc LoadEgl(const char* name) {
  return reinterpret_cast<Proc>(eglGetProcAddress(name));
}

// A display to try, best first.
struct Candidate {
  EGLenum platform;
  void* native;  // EGLDeviceEXT or EGL_DEFAULT_DISPLAY
  int device_index;
  int rank;  // lower is better
  std::string label;
};

std::vector<Candidate> EnumerateCandidates(const ContextOptions& options, std::vector<std::string>* tried) {
  std::vector<Candidate> candidates;
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto query_devices = LoadEgl<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
  auto query_device_string = LoadEgl<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");

  if (HasExtension(client_extensions, "EGL_EXT_platform_device") && query_devices && query_device_string) {
    EGLint count = 0;
    query_devices(0, nullptr, &count);
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(std::max(count, 0)));
    if (count > 0) query_devices(count, devices.data(), &count);
    std::string listed;  // "0: NVIDIA, 1: software"
    for (int i = 0; i < count; ++i) {
      const char* extensions = query_device_string(devices[i], EGL_EXTENSIONS);
      const bool software = HasExtension(extensions, "EGL_MESA_device_software");
      const bool nvidia = HasExtension(extensions, "EGL_NV_device_cuda");
      const std::string kind = nvidia ? " (NVIDIA)" : software ? " (software)" : "";
      listed += (listed.empty() ? "" : ", ") + std::to_string(i) + ": " +
                (nvidia ? "NVIDIA" : software ? "software" : "hardware");
      if (options.device_index >= 0 && i != options.device_index) continue;
      if (options.software_only && !software) {
        if (options.device_index >= 0) tried->push_back("device " + std::to_string(i) + kind + ": not a software device");
        continue;
      }
      const int rank = nvidia ? 0 : (software ? 2 : 1);
      candidates.push_back({EGL_PLATFORM_DEVICE_EXT, devices[i], i, rank, "device " + std::to_string(i) + kind});
    }
    if (options.device_index >= count) {
      throw Error(ErrorCode::kInvalidArgument,
                  "GL device " + std::to_string(options.device_index) + " does not exist: EGL lists " +
                      std::to_string(count) + (count == 1 ? " device" : " devices") +
                      (count > 0 ? " (" + listed + "), indices 0 to " + std::to_string(count - 1) : std::string()));
    }
    if (count == 0) tried->push_back("eglQueryDevicesEXT: no devices");
  } else {
    tried->push_back("EGL_EXT_platform_device: not supported by the EGL library");
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.rank < b.rank; });

  if (options.device_index >= 0) return candidates;  // that device or nothing
  if (HasExtension(client_extensions, "EGL_MESA_platform_surfaceless")) {
    candidates.push_back({EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, -1, 3, "surfaceless"});
  } else {
    tried->push_back("EGL_MESA_platform_surfaceless: not supported by the EGL library");
  }
  return candidates;
}

}  // namespace

ContextOptions DefaultContextOptions() {
  ContextOptions options;
#ifndef NDEBUG
  options.debug = true;
#endif
  if (const char* env = std::getenv("LOOM_GL_DEBUG"); env != nullptr && std::strcmp(env, "0") != 0) {
    options.debug = true;
  }
  return options;
}

std::unique_ptr<EglContext> EglContext::Create(const ContextOptions& options) {
  auto get_platform_display = LoadEgl<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
  std::vector<std::string> tried;
  if (get_platform_display == nullptr) {
    throw Error(ErrorCode::kUnavailable,
                "no OpenGL context: the EGL library lacks eglGetPlatformDisplayEXT "
                "(install libegl1 and a driver: libegl-mesa0 for llvmpipe, or the NVIDIA driver)");
  }

  for (const Candidate& candidate : EnumerateCandidates(options, &tried)) {
    auto fail = [&](const std::string& what) {
      tried.push_back(candidate.label + ": " + what + " failed (" + EglErrorName(eglGetError()) + ")");
    };
    EGLDisplay display = get_platform_display(candidate.platform, candidate.native, nullptr);
    EGLint major = 0, minor = 0;
    if (display == EGL_NO_DISPLAY) { fail("eglGetPlatformDisplayEXT"); continue; }
    if (!eglInitialize(display, &major, &minor)) { fail("eglInitialize"); continue; }
    if (!eglBindAPI(EGL_OPENGL_API)) { fail("eglBindAPI(EGL_OPENGL_API)"); continue; }

    // No surface is ever made: a config is needed only where the driver lacks
    // EGL_KHR_no_config_context.
    EGLConfig config = nullptr;
    if (!HasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
      const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint configs = 0;
      if (!eglChooseConfig(display, config_attributes, &config, 1, &configs) || configs == 0) {
        fail("eglChooseConfig");
        continue;
      }
    }
    const EGLint context_attributes[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4,
        EGL_CONTEXT_MINOR_VERSION, 5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_CONTEXT_OPENGL_DEBUG, options.debug ? EGL_TRUE : EGL_FALSE,
        EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT) { fail("eglCreateContext(OpenGL 4.5 core)"); continue; }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      fail("eglMakeCurrent without a surface");
      eglDestroyContext(display, context);
      continue;
    }

    DeviceInfo info;
    info.platform = candidate.platform == EGL_PLATFORM_DEVICE_EXT ? "device" : "surfaceless";
    info.device_index = candidate.device_index;
    info.egl_vendor = eglQueryString(display, EGL_VENDOR);
    info.gl_vendor = reinterpret_cast<const char*>(glGetString(GL_VENDOR));
    info.gl_renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    info.gl_version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    info.software = info.gl_renderer.find("llvmpipe") != std::string::npos ||
                    info.gl_renderer.find("softpipe") != std::string::npos ||
                    info.gl_renderer.find("SwiftShader") != std::string::npos;
    if (options.debug) InstallDebugOutput();
    spdlog::info("OpenGL context on EGL {} {}: {} | {} | {}", info.platform,
                 info.device_index >= 0 ? std::to_string(info.device_index) : std::string("-"),
                 info.gl_vendor, info.gl_renderer, info.gl_version);
    return std::unique_ptr<EglContext>(new EglContext(display, context, std::move(info)));
  }

  std::string message = "no OpenGL 4.5 core context could be made through EGL. Tried:";
  for (const std::string& attempt : tried) message += "\n  " + attempt;
  message += "\nOn a CPU-only machine install libegl-mesa0 and libgl1-mesa-dri (llvmpipe); "
             "on an NVIDIA machine make the driver's EGL vendor library visible to libglvnd "
             "(NVIDIA_DRIVER_CAPABILITIES must include 'graphics' in containers).";
  throw Error(ErrorCode::kUnavailable, message);
}

// The display is never terminated: EGL displays are per-process singletons, and
// eglTerminate would also end the contexts of other workers in this process.
EglContext::~EglContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
}

void EglContext::MakeCurrent() {
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
    throw Error(ErrorCode::kInternal, "eglMakeCurrent failed: " + EglErrorName(eglGetError()));
  }
}

}  // namespace loom::gl
