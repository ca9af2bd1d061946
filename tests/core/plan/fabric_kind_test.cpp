#include "core/plan/fabric_kind.h"

#include <gtest/gtest.h>

namespace loom {
namespace {

TEST(FabricKind, ByStructureAndTheShiniestYarn) {
  v1::FabricSpec knit;
  knit.mutable_knit();
  EXPECT_EQ(ClassifyFabric(knit), FabricKind::kKnitMatte);  // default yarn: specular 0.04
  v1::FabricSpec satin;
  satin.mutable_woven();
  satin.add_yarns()->mutable_specular_albedo()->set_r(0.05f);
  satin.add_yarns()->mutable_specular_albedo()->set_g(0.099f);
  EXPECT_EQ(ClassifyFabric(satin), FabricKind::kWovenMatte);
  satin.mutable_yarns(1)->mutable_specular_albedo()->set_g(0.3f);
  EXPECT_EQ(ClassifyFabric(satin), FabricKind::kWovenGlossy);
  EXPECT_EQ(ParseFabricKind(FabricKindName(FabricKind::kWovenGlossy)), FabricKind::kWovenGlossy);
  EXPECT_FALSE(ParseFabricKind("shiny").has_value());
}

}  // namespace
}  // namespace loom
