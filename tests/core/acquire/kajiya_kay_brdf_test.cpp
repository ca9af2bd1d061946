#include "core/acquire/kajiya_kay_brdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>

#include "core/acquire/hemisphere_directions.h"

namespace loom {
namespace {

constexpr float kExponents[] = {0.0f, 1.0f, 4.0f, 32.0f, 256.0f, 4096.0f};

// Unit tangents in the surface plane and tilted out of it.
std::vector<glm::vec3> Tangents() {
  std::vector<glm::vec3> tangents;
  for (float phi = 0.0f; phi < glm::pi<float>(); phi += glm::pi<float>() / 4) {
    for (float tilt : {0.0f, 0.4f, 1.2f}) {
      tangents.push_back(glm::normalize(glm::vec3(std::cos(phi), std::sin(phi), tilt)));
    }
  }
  return tangents;
}

YarnMaterial WhiteMaterial(float specular, float exponent) {
  YarnMaterial m;
  m.specular_albedo = glm::vec3(specular);
  m.diffuse_albedo = glm::vec3(1.0f - specular);
  m.specular_exponent = exponent;
  return m;
}

TEST(KajiyaKayBrdf, NormalisationMatchesClosedForms) {
  // N(p) = 1/(2 I(p)) with I(0) = π, I(1) = 2, I(2) = π/2.
  EXPECT_NEAR(KajiyaKayNormalisation(0), 1 / glm::two_pi<float>(), 1e-6f);
  EXPECT_NEAR(KajiyaKayNormalisation(1), 0.25f, 1e-6f);
  EXPECT_NEAR(KajiyaKayNormalisation(2), glm::one_over_pi<float>(), 1e-6f);
  EXPECT_TRUE(std::isfinite(KajiyaKayNormalisation(1e7f)));
}

TEST(KajiyaKayBrdf, LambertianPartIsAlbedoOverPi) {
  const KajiyaKayBrdf brdf(WhiteMaterial(0.0f, 32.0f));
  const glm::vec3 n(0, 0, 1), t(1, 0, 0);
  for (const glm::vec3& l : HemisphereGridDirections(16)) {
    for (const glm::vec3& v : HemisphereGridDirections(16)) {
      EXPECT_EQ(brdf.Evaluate(n, t, l, v), glm::vec3(glm::one_over_pi<float>()));
    }
  }
  EXPECT_EQ(brdf.Evaluate(n, t, {0, 0, -1}, {0, 0, 1}), glm::vec3(0.0f));  // light below
  // A view below the shading normal's horizon (a silhouette whose triangle faces it)
  // is shaded: sidedness is the caller's.
  EXPECT_EQ(brdf.Evaluate(n, t, {0, 0, 1}, {0.6f, 0, -0.1f}), glm::vec3(glm::one_over_pi<float>()));
}

TEST(KajiyaKayBrdf, ReflectedRadianceExceedsTheWhiteLambertianBoundByAtMostTheSpecularShare) {
  // Under unit irradiance the reflected radiance is f_r·cos θ_l; with ρ_d + ρ_s = 1
  // it never exceeds cos θ_l/π by more than ρ_s·(N(p) − 1/π)·cos θ_l.
  const glm::vec3 n(0, 0, 1);
  const auto directions = HemisphereGridDirections(16 * 16);
  for (float specular : {0.0f, 0.04f, 0.5f, 1.0f}) {
    for (float exponent : kExponents) {
      const KajiyaKayBrdf brdf(WhiteMaterial(specular, exponent));
      const float share = specular * (KajiyaKayNormalisation(exponent) - glm::one_over_pi<float>());
      float worst = -1.0f;
      for (const glm::vec3& t : Tangents()) {
        for (const glm::vec3& l : directions) {
          for (const glm::vec3& v : directions) {
            const glm::vec3 radiance = brdf.Evaluate(n, t, l, v) * l.z;
            const float bound = (glm::one_over_pi<float>() + std::max(share, 0.0f)) * l.z;
            worst = std::max(worst, radiance.r - bound);
          }
        }
      }
      EXPECT_LE(worst, 1e-6f) << "specular " << specular << " exponent " << exponent;
    }
  }
}

// ∫ f_r(l, v) cos θ_v dω_v over the hemisphere, as the mean over an equal-area
// grid of view directions (each cell 2π/count sr).
float DirectionalAlbedo(const KajiyaKayBrdf& brdf, glm::vec3 t, glm::vec3 l, const std::vector<glm::vec3>& views) {
  double sum = 0.0;
  for (const glm::vec3& v : views) sum += brdf.Evaluate({0, 0, 1}, t, l, v).r * v.z;
  return static_cast<float>(sum * glm::two_pi<double>() / static_cast<double>(views.size()));
}

TEST(KajiyaKayBrdf, DirectionalAlbedoIsAtMostOne) {
  const auto lights = HemisphereGridDirections(5 * 5);
  const auto views = HemisphereGridDirections(128 * 128);
  for (float exponent : {1.0f, 32.0f, 256.0f}) {
    // The fibre lobe alone, and a white material sharing its energy.
    for (float specular : {1.0f, 0.3f}) {
      const KajiyaKayBrdf brdf(WhiteMaterial(specular, exponent));
      float largest = 0.0f;
      for (const glm::vec3& t : Tangents()) {
        for (const glm::vec3& l : lights) largest = std::max(largest, DirectionalAlbedo(brdf, t, l, views));
      }
      EXPECT_LE(largest, 1.0f + 2e-3f) << "specular " << specular << " exponent " << exponent;
      EXPECT_GT(largest, 1.0f - specular * 0.4f) << "specular " << specular << " exponent " << exponent;
    }
  }
}

TEST(KajiyaKayBrdf, LobeAlbedoBoundIsTightForLightPerpendicularToTheFibre) {
  // Light at the zenith, fibre in the surface: the lobe's albedo is exactly
  // I(p+2)/I(p) = (p+1)/(p+2), so the normalisation wastes no energy.
  const auto views = HemisphereGridDirections(400 * 400);
  for (float exponent : {0.0f, 1.0f, 8.0f, 64.0f}) {
    const KajiyaKayBrdf brdf(WhiteMaterial(1.0f, exponent));
    const float albedo = DirectionalAlbedo(brdf, {1, 0, 0}, {0, 0, 1}, views);
    const float expected = (exponent + 1) / (exponent + 2);
    EXPECT_NEAR(albedo, expected, 0.005f) << exponent;
  }
}

TEST(KajiyaKayBrdf, LobePeaksOnTheMirrorCone) {
  const KajiyaKayBrdf brdf(WhiteMaterial(1.0f, 64.0f));
  const glm::vec3 n(0, 0, 1), t(1, 0, 0);
  const glm::vec3 l = glm::normalize(glm::vec3(0.5f, 0.2f, 0.8f));
  // Mirror cone: t·v = −t·l. Both of these are on it, this one is not.
  const glm::vec3 on_cone = glm::normalize(glm::vec3(-0.5f, -0.2f, 0.8f));
  const glm::vec3 also_on_cone = glm::vec3(-l.x, std::sqrt(1 - l.x * l.x - 0.3f * 0.3f), 0.3f);
  const glm::vec3 off_cone = glm::normalize(glm::vec3(0.5f, -0.2f, 0.8f));
  const float peak = KajiyaKayNormalisation(64.0f);
  EXPECT_NEAR(brdf.Evaluate(n, t, l, on_cone).r, peak, 1e-4f);
  EXPECT_NEAR(brdf.Evaluate(n, t, l, also_on_cone).r, peak, 1e-4f);
  EXPECT_LT(brdf.Evaluate(n, t, l, off_cone).r, 0.01f * peak);
}

TEST(KajiyaKayBrdf, DegenerateInputsStayFinite) {
  YarnMaterial m = WhiteMaterial(0.5f, 1e6f);
  const KajiyaKayBrdf brdf(m);
  const glm::vec3 n(0, 0, 1);
  for (const glm::vec3& t : {glm::vec3(0.0f), glm::vec3(0, 0, 1), glm::vec3(1.0000001f, 0, 0)}) {
    for (const glm::vec3& l : {glm::vec3(0, 0, 1), glm::vec3(1, 0, 1e-7f)}) {
      const glm::vec3 f = brdf.Evaluate(n, t, l, l);
      EXPECT_TRUE(std::isfinite(f.r) && f.r >= 0.0f);
    }
  }
  // No fibre direction: no lobe, only the diffuse part.
  EXPECT_EQ(brdf.Evaluate(n, glm::vec3(0.0f), {0, 0, 1}, {0, 0, 1}), brdf.diffuse());
}

}  // namespace
}  // namespace loom
