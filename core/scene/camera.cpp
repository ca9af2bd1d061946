#include "core/scene/camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace loom {

CameraMatrices MakeCameraMatrices(const v1::Camera& camera, float aspect) {
  CameraMatrices matrices;
  matrices.position = ToGlm(camera.position());
  matrices.view = glm::lookAt(matrices.position, ToGlm(camera.target()), ToGlm(camera.up()));
  if (camera.projection() == v1::PROJECTION_ORTHOGRAPHIC) {
    const float half_height = 0.5f * camera.ortho_height();
    const float half_width = half_height * aspect;
    matrices.projection = glm::ortho(-half_width, half_width, -half_height, half_height, camera.near(), camera.far());
  } else {
    matrices.projection = glm::perspective(glm::radians(camera.fov_y_degrees()), aspect, camera.near(), camera.far());
  }
  return matrices;
}

}  // namespace loom
