#pragma once
// Test support: runs a fragment shader over every pixel of a float target and
// returns the pixels, to check GLSL functions against their C++ twins.

#include <string>

#include "core/image/image.h"

namespace loom::gl {

// `fragment` is a full fragment shader (it may #include embedded .glsl files); it
// writes location 0. Needs a current context.
Image RunFullscreenPass(const std::string& fragment, int width, int height);

}  // namespace loom::gl
