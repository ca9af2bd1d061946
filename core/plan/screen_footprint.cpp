#include "core/plan/screen_footprint.h"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "core/scene/camera.h"

namespace loom {

TileFootprint MeasureTileFootprint(const v1::SceneSpec& scene, const SceneMesh& mesh) {
  TileFootprint footprint;
  if (mesh.object == nullptr || !mesh.object->has_fabric()) return footprint;
  const double width = scene.render().width(), height = scene.render().height();
  const CameraMatrices camera = MakeCameraMatrices(scene.camera(), static_cast<float>(width / height));
  const glm::mat4 view_projection = camera.projection * camera.view;
  const double tiles_per_uv = static_cast<double>(mesh.object->fabric().repeat_u()) * mesh.object->fabric().repeat_v();
  const TriangleMesh& m = mesh.mesh;
  double largest = 0.0, smallest = INFINITY;
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    glm::dvec2 pixel[3], uv[3];
    bool usable = true;
    double low_x = INFINITY, high_x = -INFINITY, low_y = INFINITY, high_y = -INFINITY;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.indices[3 * t + k];
      const glm::vec4 clip = view_projection * glm::vec4(m.positions[v], 1.0f);
      if (!(clip.w > 0.0f) || clip.z < -clip.w) {  // behind the camera or the near plane
        usable = false;
        break;
      }
      pixel[k] = {(clip.x / clip.w * 0.5 + 0.5) * width, (0.5 - clip.y / clip.w * 0.5) * height};
      uv[k] = m.uvs[v];
      low_x = std::min(low_x, pixel[k].x), high_x = std::max(high_x, pixel[k].x);
      low_y = std::min(low_y, pixel[k].y), high_y = std::max(high_y, pixel[k].y);
    }
    if (!usable || high_x < 0 || low_x > width || high_y < 0 || low_y > height) continue;
    const auto area = [](const glm::dvec2* p) {
      const glm::dvec2 a = p[1] - p[0], b = p[2] - p[0];
      return 0.5 * std::abs(a.x * b.y - a.y * b.x);
    };
    const double tiles = area(uv) * tiles_per_uv;
    if (!(tiles > 0.0)) continue;
    const double side = std::sqrt(area(pixel) / tiles);
    largest = std::max(largest, side);
    smallest = std::min(smallest, side);
    ++footprint.visible_triangles;
  }
  if (footprint.visible_triangles > 0) {
    footprint.largest_pixels = largest;
    footprint.smallest_pixels = smallest;
  }
  return footprint;
}

}  // namespace loom
