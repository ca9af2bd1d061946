#include "core/animate/knit_cloth.h"

#include <string>

#include "core/util/error.h"

namespace loom::animate {

KnitCloth FlatKnitCloth(int across, int along, float course_spacing,
                        float wale_spacing, glm::vec3 origin, glm::vec3 course,
                        glm::vec3 wale) {
  if (across < 2 || along < 2) {
    throw Error(ErrorCode::kInvalidArgument,
                "knit cloth: " + std::to_string(across) + " × " +
                    std::to_string(along) + " loops; needs at least 2 × 2");
  }
  if (!(course_spacing > 0.0f && wale_spacing > 0.0f)) {
    throw Error(ErrorCode::kInvalidArgument,
                "knit cloth: loop spacings must be > 0");
  }
  if (!(glm::length(glm::cross(course, wale)) > 1e-6f)) {
    throw Error(ErrorCode::kInvalidArgument,
                "knit cloth: course and wale axes are parallel");
  }
  KnitCloth cloth;
  cloth.across = across;
  cloth.along = along;
  cloth.course_spacing = course_spacing;
  cloth.wale_spacing = wale_spacing;
  course = glm::normalize(course);
  wale = glm::normalize(wale);
  cloth.positions.reserve(static_cast<size_t>(across) * along);
  for (int j = 0; j < along; ++j) {
    for (int i = 0; i < across; ++i) {
      cloth.positions.push_back(
          origin + static_cast<float>(i) * course_spacing * course +
          static_cast<float>(j) * wale_spacing * wale);
    }
  }
  return cloth;
}

} // namespace loom::animate
