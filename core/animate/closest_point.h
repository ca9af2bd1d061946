#pragma once
// The point of a triangle nearest a given point, with its barycentric weights:
// what a knit point's distance to a cloth triangle and the split of their contact
// force between the triangle's corners both need (Ericson, Real-Time Collision
// Detection §5.1.5).

#include <glm/glm.hpp>

namespace loom::animate {

struct TrianglePoint {
  glm::vec3 point{0.0f};    // on the triangle (its edges included)
  glm::vec3 weights{0.0f};  // of a, b, c: ≥ 0, summing to 1
};

// Degenerate triangles are handled: the nearest point of their segment or corner.
TrianglePoint ClosestPointOnTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c);

// The barycentric weights of p's projection onto the triangle's plane (negative
// outside it); all zero for a degenerate triangle.
glm::vec3 ProjectedWeights(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c);

}  // namespace loom::animate
