// The equal-area hemisphere map of core/acquire/hemisphere_directions.cpp, in GLSL:
// Shirley–Chiu concentric square ↔ disk, then Lambert's lift disk ↔ hemisphere.
// The per-view lookup table T(v) is stored on this map's k×k grid, so the renderer
// finds a view's place in the table with HemisphereGridCoordinates. Keep the two
// implementations identical (tests/core/gl/hemisphere_map_glsl_test.cpp).

#include "constants.glsl"

vec2 ConcentricSquareToDisk(vec2 square) {
  vec2 p = 2.0 * square - 1.0;
  if (p.x == 0.0 && p.y == 0.0) return vec2(0.0);
  float r, phi;
  if (abs(p.x) > abs(p.y)) {
    r = p.x;
    phi = kQuarterPi * (p.y / p.x);
  } else {
    r = p.y;
    phi = kHalfPi - kQuarterPi * (p.x / p.y);
  }
  return r * vec2(cos(phi), sin(phi));
}

vec2 ConcentricDiskToSquare(vec2 disk) {
  float r = length(disk);
  float phi = (disk.x == 0.0 && disk.y == 0.0) ? 0.0 : atan(disk.y, disk.x);  // (−π, π]
  if (phi < -kQuarterPi) phi += 2.0 * kPi;                                     // [−π/4, 7π/4)
  vec2 p;
  if (phi < kQuarterPi) {
    p = vec2(r, r * phi / kQuarterPi);
  } else if (phi < 3.0 * kQuarterPi) {
    p = vec2(r * (kHalfPi - phi) / kQuarterPi, r);
  } else if (phi < 5.0 * kQuarterPi) {
    p = vec2(-r, -r * (phi - kPi) / kQuarterPi);
  } else {
    p = vec2(r * (phi - 3.0 * kHalfPi) / kQuarterPi, -r);
  }
  return clamp(0.5 * (p + 1.0), 0.0, 1.0);
}

vec3 SquareToHemisphere(vec2 square) {
  vec2 d = ConcentricSquareToDisk(square);
  float r2 = min(dot(d, d), 1.0);
  return vec3(d * sqrt(2.0 - r2), 1.0 - r2);
}

// Any direction; one below the horizon is projected onto it first.
vec2 HemisphereToSquare(vec3 direction) {
  direction.z = max(direction.z, 0.0);
  float len = length(direction);
  if (!(len > 0.0)) return vec2(0.5);
  direction /= len;
  return ConcentricDiskToSquare(direction.xy / sqrt(1.0 + direction.z));
}

// Continuous grid coordinates on a k×k direction grid: direction (col, row) sits
// at (col, row); the range is [−½, k − ½]².
vec2 HemisphereGridCoordinates(vec3 direction, float side) {
  return HemisphereToSquare(direction) * side - 0.5;
}
