#include "core/fit/lafortune_brdf.h"

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include "core/acquire/radiance_samples.h"

namespace loom {
namespace {

TEST(LafortuneBrdf, DiffuseIsRhoTimesCosine) {
  LafortuneBrdf brdf;
  brdf.rho = glm::vec3(0.1f, 0.2f, 0.3f);
  const glm::vec3 l = glm::normalize(glm::vec3(0.3f, 0.4f, 0.8f));
  const glm::vec3 r = brdf.Evaluate(l, glm::vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(r.x, 0.1f * l.z);
  EXPECT_FLOAT_EQ(r.z, 0.3f * l.z);
  EXPECT_EQ(brdf.Evaluate(glm::vec3(1, 0, -0.1f), glm::vec3(0, 0, 1)), glm::vec3(0.0f)) << "light below the horizon";
}

TEST(LafortuneBrdf, LobeIsZeroForNegativeArgument) {
  LafortuneBrdf brdf;
  brdf.lobe_count = 1;
  brdf.lobes[0] = {glm::vec3(-1.0f), glm::vec3(-1.0f), glm::vec3(1.0f), glm::vec3(2.0f)};
  const glm::vec3 l = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f));
  // Mirror direction: argument 0.36 + 0.64 = 1.
  EXPECT_NEAR(brdf.Evaluate(l, glm::vec3(-l.x, -l.y, l.z)).x, 1.0f * l.z, 1e-6);
  // Same side, grazing: argument −0.99·… + small < 0, so the lobe is off.
  const glm::vec3 v = glm::normalize(glm::vec3(0.99f, 0.0f, 0.1f));
  EXPECT_EQ(brdf.Evaluate(l, v), glm::vec3(0.0f));
}

TEST(LafortuneBrdf, PackUnpackRoundTrip) {
  LafortuneBrdf brdf;
  brdf.lobe_count = 2;
  brdf.rho = glm::vec3(0.1f, 0.2f, 0.3f);
  brdf.lobes[1] = {glm::vec3(-1.0f), glm::vec3(-2.0f), glm::vec3(3.0f), glm::vec3(4.0f, 5.0f, 6.0f)};
  LafortuneBrdf copy;
  copy.lobe_count = 2;
  double x[9];
  for (int c = 0; c < 3; ++c) {
    brdf.PackChannel(c, x);
    copy.UnpackChannel(c, x);
  }
  EXPECT_EQ(copy.rho, brdf.rho);
  EXPECT_EQ(copy.lobes[1].n, brdf.lobes[1].n);
  EXPECT_EQ(copy.lobes[1].cy, brdf.lobes[1].cy);
}

TEST(TexelFrame, MapsNormalToZAndTangentToX) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.2f, -0.3f, 0.9f));
  const glm::vec3 t = TexelTangent(n);
  EXPECT_NEAR(glm::dot(t, n), 0.0f, 1e-6);
  EXPECT_GT(t.x, 0.0f);
  EXPECT_NEAR(glm::dot(glm::cross(n, glm::vec3(1, 0, 0)), t), 0.0f, 1e-6) << "in the plane of n and x";
  const TexelFrame frame(n, t);
  const glm::vec3 nz = frame.ToLocal(n);
  const glm::vec3 tx = frame.ToLocal(t);
  EXPECT_NEAR(nz.z, 1.0f, 1e-6);
  EXPECT_NEAR(tx.x, 1.0f, 1e-6);
  EXPECT_NEAR(frame.ToLocal(glm::cross(n, t)).y, 1.0f, 1e-6);
}

}  // namespace
}  // namespace loom
