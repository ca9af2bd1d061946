#include "core/acquire/yarn_shading.h"

#include <gtest/gtest.h>

#include "core/fabric/yarn_material.h"
#include "core/spec/defaults.h"

namespace loom {
namespace {

v1::YarnSpec Yarn(v1::YarnShading shading) {
  v1::FabricSpec fabric;
  fabric.mutable_woven();
  v1::YarnSpec& yarn = *fabric.add_yarns();
  if (shading != v1::YARN_SHADING_UNSPECIFIED) yarn.set_shading(shading);
  yarn.set_roughness(0.3f);
  return WithDefaults(fabric).yarns(0);
}

TEST(YarnShading, EachYarnShadesWithTheModelItsSpecNames) {
  const glm::vec3 n(0, 0, 1), t(1, 0, 0);
  const glm::vec3 l = glm::normalize(glm::vec3(0.2f, 0.5f, 1)), v = glm::normalize(glm::vec3(-0.3f, -0.4f, 1));
  const YarnMaterial kajiya_kay = MakeYarnMaterial(Yarn(v1::YARN_SHADING_UNSPECIFIED));
  const YarnMaterial microflake = MakeYarnMaterial(Yarn(v1::YARN_SHADING_MICROFLAKE));
  EXPECT_EQ(kajiya_kay.model, YarnShadingModel::kKajiyaKay);
  EXPECT_EQ(microflake.model, YarnShadingModel::kMicroflake);
  EXPECT_EQ(microflake.roughness, 0.3f);
  EXPECT_EQ(microflake.height_scale, 1.0f);  // the defaults
  EXPECT_EQ(microflake.lambert_blend, 1.0f);
  EXPECT_EQ(YarnBrdf(kajiya_kay).Evaluate(n, t, l, v), KajiyaKayBrdf(kajiya_kay).Evaluate(n, t, l, v));
  EXPECT_EQ(YarnBrdf(microflake).Evaluate(n, t, l, v), FibreMicroflakeBrdf(microflake).Evaluate(n, t, l, v));
  EXPECT_NE(YarnBrdf(microflake).Evaluate(n, t, l, v), YarnBrdf(kajiya_kay).Evaluate(n, t, l, v));
  EXPECT_EQ(YarnBrdf(microflake).diffuse(), YarnBrdf(kajiya_kay).diffuse());
}

}  // namespace
}  // namespace loom
