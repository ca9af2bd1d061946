// Fibre walks (core/acquire/fibre_walk.h) in a flat bed of fibres deep enough to be a
// half-space: over every order of scattering it reflects about what the yarn's diffuse
// albedo says, and single scattering alone does not.
#include "core/acquire/fibre_walk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>

namespace loom {
namespace {

// Fibres along x filling z ∈ [−depth, 0], extinction σ per unit of length.
struct BedMedium {
  float sigma = 20.0f, depth = 10.0f;
  VolumeSample Sample(glm::vec3 p) const {
    VolumeSample sample;
    sample.extinction = p.z <= 0.0f && p.z >= -depth ? sigma : 0.0f;
    sample.fibre = glm::vec3(1.0f, 0.0f, 0.0f);
    return sample;
  }
  float ModelLength(glm::vec3 v) const { return glm::length(v); }
  float step() const { return 0.005f; }
  glm::vec2 Interval(glm::vec3 origin, glm::vec3 direction) const {
    if (direction.z == 0.0f) return {0.0f, 100.0f};
    const float a = (-depth - origin.z) / direction.z, b = -origin.z / direction.z;
    return {std::max(std::min(a, b), 0.0f), std::max(a, b)};
  }
};

struct BedReflectance {
  glm::vec3 single{0.0f}, all{0.0f};
};

// π L / E of the bed lit and seen along its normal, by `samples` walks.
BedReflectance Reflect(const YarnMaterial& material, int samples) {
  const BedMedium bed;
  const std::vector<YarnMaterial> materials{material};
  const glm::vec3 albedo = FibreAlbedo(material.diffuse_albedo);
  const glm::vec3 up(0.0f, 0.0f, 1.0f);
  RandomStream random(7, RandomStream::kFibreWalk, 0);
  BedReflectance result;
  for (int i = 0; i < samples; ++i) {
    // The view ray's first event (the bed is thick: every ray has one).
    const auto event = FreeFlight(bed, glm::vec3(0.0f, 0.0f, 1.0f), -up, -std::log(1.0f - random.Uniform()),
                                  random.Uniform());
    if (!event) continue;
    const auto lit = [&](glm::vec3 q) { return std::exp(-bed.sigma * -q.z); };  // T_l straight up
    const glm::vec3 single = FibreDiffuseScattering(albedo, event->sample.fibre, up) * lit(event->position);
    glm::vec3 scattered(0.0f);
    WalkFibres(bed, materials, event->position, event->sample, random,
               [&](glm::vec3 q, const VolumeSample& at, glm::vec3 throughput) {
                 scattered += throughput * FibreDiffuseScattering(albedo, at.fibre, up) * lit(q);
               });
    result.single += single;
    result.all += single + scattered;
  }
  result.single *= glm::pi<float>() / static_cast<float>(samples);
  result.all *= glm::pi<float>() / static_cast<float>(samples);
  return result;
}

TEST(FibreWalk, AThickBedReflectsItsYarnsAlbedoOverEveryOrder) {
  YarnMaterial material;
  material.diffuse_albedo = glm::vec3(0.62f, 0.3f, 0.08f);
  const BedReflectance bed = Reflect(material, 20000);
  for (int c = 0; c < 3; ++c) {
    SCOPED_TRACE(c);
    EXPECT_NEAR(bed.all[c], material.diffuse_albedo[c], 0.2f * material.diffuse_albedo[c]);
  }
  // Light yarn's light is mostly scattered more than once.
  EXPECT_LT(bed.single.r, 0.5f * bed.all.r);
}

TEST(FibreWalk, AlbedoIsPhysicalAndGrowsWithTheDiffuseAlbedo) {
  float previous = -1.0f;
  for (float rho = 0.0f; rho <= 1.0f; rho += 0.05f) {
    const float alpha = FibreAlbedo(glm::vec3(rho)).r;
    EXPECT_GE(alpha, rho - 1e-3f);
    EXPECT_LE(alpha, 1.0f);
    EXPECT_GT(alpha, previous);
    previous = alpha;
  }
  EXPECT_NEAR(FibreAlbedo(glm::vec3(0.0f)).r, 0.0f, 1e-4f);
}

}  // namespace
}  // namespace loom
