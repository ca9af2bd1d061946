#include "core/animate/closest_point.h"

namespace loom::animate {

TrianglePoint ClosestPointOnTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const auto at = [&](float u, float v, float w) { return TrianglePoint{u * a + v * b + w * c, glm::vec3(u, v, w)}; };
  // Voronoi regions of the corners, then of the edges, then the face.
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return at(1, 0, 0);
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return at(0, 1, 0);
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
    const float t = d1 - d3 > 0.0f ? d1 / (d1 - d3) : 0.0f;
    return at(1 - t, t, 0);
  }
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return at(0, 0, 1);
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
    const float t = d2 - d6 > 0.0f ? d2 / (d2 - d6) : 0.0f;
    return at(1 - t, 0, t);
  }
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f) {
    const float denominator = (d4 - d3) + (d5 - d6);
    const float t = denominator > 0.0f ? (d4 - d3) / denominator : 0.0f;
    return at(0, 1 - t, t);
  }
  const float sum = va + vb + vc;
  if (!(sum > 0.0f)) return at(1, 0, 0);  // degenerate: every region test failed
  const float v = vb / sum, w = vc / sum;
  return at(1 - v - w, v, w);
}

glm::vec3 ProjectedWeights(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d00 = glm::dot(ab, ab), d01 = glm::dot(ab, ac), d11 = glm::dot(ac, ac);
  const float d20 = glm::dot(ap, ab), d21 = glm::dot(ap, ac);
  const float denominator = d00 * d11 - d01 * d01;
  if (!(denominator > 0.0f)) return glm::vec3(0.0f);
  const float v = (d11 * d20 - d01 * d21) / denominator, w = (d00 * d21 - d01 * d20) / denominator;
  return glm::vec3(1.0f - v - w, v, w);
}

}  // namespace loom::animate
