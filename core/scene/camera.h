#pragma once
// View and projection matrices of a SceneSpec camera (GL conventions: right-handed
// view space looking down −z, clip z in [−1, 1]).

#include <glm/glm.hpp>

#include "core/spec/spec_math.h"
#include "loom/v1/scene.pb.h"

namespace loom {

struct CameraMatrices {
  glm::mat4 view{1.0f};
  glm::mat4 projection{1.0f};
  glm::vec3 position{0.0f};
};

// `camera` with defaults applied (core/spec/defaults.h); aspect = width / height.
CameraMatrices MakeCameraMatrices(const v1::Camera& camera, float aspect);

}  // namespace loom
