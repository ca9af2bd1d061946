#include "core/acquire/hemisphere_directions.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <string>

#include "core/util/error.h"

namespace loom {

glm::vec2 ConcentricSquareToDisk(glm::vec2 square) {
  const glm::vec2 p = 2.0f * square - 1.0f;  // [−1, 1]²
  if (p.x == 0.0f && p.y == 0.0f) return {0.0f, 0.0f};
  // The square's concentric rings map to circles: the larger coordinate is the
  // radius, the smaller one sweeps the angle linearly across the ring's side.
  constexpr float kQuarterPi = glm::quarter_pi<float>();
  float r, phi;
  if (std::abs(p.x) > std::abs(p.y)) {
    r = p.x;
    phi = kQuarterPi * (p.y / p.x);
  } else {
    r = p.y;
    phi = glm::half_pi<float>() - kQuarterPi * (p.x / p.y);
  }
  return r * glm::vec2(std::cos(phi), std::sin(phi));
}

glm::vec2 ConcentricDiskToSquare(glm::vec2 disk) {
  const float r = std::hypot(disk.x, disk.y);
  float phi = std::atan2(disk.y, disk.x);  // (−π, π]
  constexpr float kQuarterPi = glm::quarter_pi<float>();
  if (phi < -kQuarterPi) phi += glm::two_pi<float>();  // [−π/4, 7π/4)
  // Which side of the square the angle falls on decides which coordinate is the
  // radius; the other one is the angle within that side, as in the forward map.
  glm::vec2 p;
  if (phi < kQuarterPi) {
    p = {r, r * phi / kQuarterPi};
  } else if (phi < 3.0f * kQuarterPi) {
    p = {r * (glm::half_pi<float>() - phi) / kQuarterPi, r};
  } else if (phi < 5.0f * kQuarterPi) {
    p = {-r, -r * (phi - glm::pi<float>()) / kQuarterPi};
  } else {
    p = {r * (phi - 3.0f * glm::half_pi<float>()) / kQuarterPi, -r};
  }
  return glm::clamp(0.5f * (p + 1.0f), 0.0f, 1.0f);
}

glm::vec3 SquareToHemisphere(glm::vec2 square) {
  const glm::vec2 d = ConcentricSquareToDisk(square);
  const float r2 = std::min(glm::dot(d, d), 1.0f);
  // Lambert's lift: the disk area πr² inside radius r equals the solid angle
  // 2π(1 − z) above z = 1 − r², so uniform area stays uniform solid angle.
  const float scale = std::sqrt(2.0f - r2);
  return {d.x * scale, d.y * scale, 1.0f - r2};
}

glm::vec2 HemisphereToSquare(glm::vec3 direction) {
  direction.z = std::max(direction.z, 0.0f);
  const float length = glm::length(direction);
  if (!(length > 0.0f)) return {0.5f, 0.5f};
  direction /= length;
  // Inverse lift: r² = 1 − z and |xy| = r·√(2 − r²) = r·√(1 + z).
  const glm::vec2 disk = glm::vec2(direction.x, direction.y) / std::sqrt(1.0f + direction.z);
  return ConcentricDiskToSquare(disk);
}

uint32_t HemisphereGridSide(uint32_t count) {
  const auto side = static_cast<uint32_t>(std::lround(std::sqrt(static_cast<double>(count))));
  if (count == 0 || uint64_t{side} * side != count) {
    throw Error(ErrorCode::kInvalidArgument,
                "direction count " + std::to_string(count) + " is not a non-zero perfect square (k×k grid)");
  }
  return side;
}

std::vector<glm::vec3> HemisphereGridDirections(uint32_t count) {
  const uint32_t side = HemisphereGridSide(count);
  std::vector<glm::vec3> directions;
  directions.reserve(count);
  for (uint32_t row = 0; row < side; ++row) {
    for (uint32_t col = 0; col < side; ++col) {
      const glm::vec2 square((col + 0.5f) / side, (row + 0.5f) / side);
      directions.push_back(SquareToHemisphere(square));
    }
  }
  return directions;
}

std::vector<glm::vec3> MirroredThroughTheSurface(std::vector<glm::vec3> directions) {
  for (glm::vec3& d : directions) d.z = -d.z;
  return directions;
}

glm::vec2 HemisphereGridCoordinates(glm::vec3 direction, uint32_t side) {
  return HemisphereToSquare(direction) * static_cast<float>(side) - 0.5f;
}

}  // namespace loom
