#include "core/fit/lafortune_brdf.h"

#include <cmath>

#include "core/util/vector_math.h"

namespace loom {

void LafortuneBrdf::PackChannel(int c, double* x) const {
  x[0] = rho[c];
  for (uint32_t i = 0; i < lobe_count; ++i) {
    double* lobe = x + 1 + 4 * i;
    lobe[0] = lobes[i].cx[c];
    lobe[1] = lobes[i].cy[c];
    lobe[2] = lobes[i].cz[c];
    lobe[3] = lobes[i].n[c];
  }
}

void LafortuneBrdf::UnpackChannel(int c, const double* x) {
  rho[c] = static_cast<float>(x[0]);
  for (uint32_t i = 0; i < lobe_count; ++i) {
    const double* lobe = x + 1 + 4 * i;
    lobes[i].cx[c] = static_cast<float>(lobe[0]);
    lobes[i].cy[c] = static_cast<float>(lobe[1]);
    lobes[i].cz[c] = static_cast<float>(lobe[2]);
    lobes[i].n[c] = static_cast<float>(lobe[3]);
  }
}

glm::vec3 LafortuneBrdf::Evaluate(glm::vec3 light, glm::vec3 view) const {
  if (light.z <= 0.0f) return glm::vec3(0.0f);
  const LobeArgument a = MakeLobeArgument(light, view);
  glm::vec3 result;
  double x[1 + 4 * kMaxLafortuneLobes];
  for (int c = 0; c < 3; ++c) {
    PackChannel(c, x);
    result[c] = static_cast<float>(light.z * LafortuneChannel(x, lobe_count, a));
  }
  return result;
}

bool LafortuneBrdf::AllFinite() const {
  auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(rho)) return false;
  for (const LafortuneLobe& lobe : lobes) {
    if (!finite(lobe.cx) || !finite(lobe.cy) || !finite(lobe.cz) || !finite(lobe.n)) return false;
  }
  return true;
}

TexelFrame::TexelFrame(glm::vec3 normal, glm::vec3 tangent)
    : normal_(normal), tangent_(tangent), bitangent_(glm::cross(normal, tangent)) {}

}  // namespace loom
