#include "core/animate/knit_cloth.h"

#include <string>

#include "core/util/error.h"

namespace loom::animate {

KnitCloth FlatKnitCloth(int across, int along, float course_spacing, float wale_spacing, glm::vec3 origin,
                        glm::vec3 course, glm::vec3 wale) {
  if (across < 2 || along < 2) {
    throw Error(ErrorCode::kInvalidArgument, "knit cloth: " + std::to_string(across) + " × " + std::to_string(along) +
                                                 " loops; needs at least 2 × 2");
  }
  if (!(course_spacing > 0.0f && wale_spacing > 0.0f)) {
    throw Error(ErrorCode::kInvalidArgument, "knit cloth: loop spacings must be > 0");
  }
  if (!(glm::length(glm::cross(course, wale)) > 1e-6f)) {
    throw Error(ErrorCode::kInvalidArgument, "knit cloth: course and wale axes are parallel");
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
      cloth.positions.push_back(origin + static_cast<float>(i) * course_spacing * course +
                                static_cast<float>(j) * wale_spacing * wale);
    }
  }
  return cloth;
}

std::vector<glm::uvec3> KnitCloth::Triangles() const {
  std::vector<glm::uvec3> triangles;
  triangles.reserve(2 * static_cast<size_t>(across - 1) * (along - 1));
  for (int j = 0; j + 1 < along; ++j) {
    for (int i = 0; i + 1 < across; ++i) {
      const auto corner = [&](int di, int dj) { return static_cast<unsigned>(Index(i + di, j + dj)); };
      triangles.emplace_back(corner(0, 0), corner(1, 0), corner(0, 1));
      triangles.emplace_back(corner(1, 0), corner(1, 1), corner(0, 1));
    }
  }
  return triangles;
}

bool KnitCloth::Adjacent(size_t point, size_t triangle, int rings) const {
  const int pi = static_cast<int>(point % across), pj = static_cast<int>(point / across);
  const size_t cell = triangle / 2;
  const int ci = static_cast<int>(cell % (across - 1)), cj = static_cast<int>(cell / (across - 1));
  // The cell's corners span [ci, ci + 1] × [cj, cj + 1].
  return ci + 1 >= pi - rings && ci <= pi + rings && cj + 1 >= pj - rings && cj <= pj + rings;
}

}  // namespace loom::animate
