#include "core/fabric/woven_tile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/spec/defaults.h"
#include "fabric_specs.h"
#include "yarn_clearance.h"

namespace loom {
namespace {

constexpr float kTolerance = 0.02f;

v1::FabricSpec With(v1::FabricSpec fabric, float inclination, float radius) {
  fabric.mutable_woven()->set_inclination_degrees(inclination);
  fabric.mutable_yarns(0)->set_radius(radius);
  return WithDefaults(fabric);
}

TEST(WovenTile, YarnSurfacesNeverInterpenetrate) {
  for (const float gap : {0.0f, 0.3f}) {
    for (const float inclination : {5.0f, 20.0f, 45.0f, 60.0f}) {
      for (const NamedFabric& fabric : WovenFabrics(gap)) {
        const TileYarns tile = BuildWovenYarns(With(fabric.spec, inclination, 0.5f), 12);
        const Clearance clearance = SurfaceClearance(tile, 16);
        EXPECT_GE(clearance.ratio, 1.0f - kTolerance)
            << fabric.name << " gap " << gap << " inclination " << inclination << " near (" << clearance.where.x
            << ", " << clearance.where.y << ", " << clearance.where.z << ")";
      }
    }
  }
}

TEST(WovenTile, CentreLinesStayTwoHalfThicknessesApart) {
  // The plain measure of the issue: centre-line distance against twice the yarn radius
  // (here the half-thickness), periodic copies included.
  for (const NamedFabric& fabric : WovenFabrics(0.0f)) {
    TileYarns tile = BuildWovenYarns(WithDefaults(fabric.spec), 24);
    for (PeriodicYarn& yarn : tile.yarns) {
      for (glm::vec2& section : yarn.section) section = glm::vec2(section.y);
      yarn.shape = SectionShape::kEllipse;
    }
    EXPECT_GE(MeasureClearance(tile).ratio, 1.0f - kTolerance) << fabric.name;
  }
}

TEST(WovenTile, ThreadsFollowTheWeaveWithTheInclinationAsSteepestSlope) {
  const float inclination = 30.0f;
  const TileYarns tile = BuildWovenYarns(With(WovenSpec(v1::WEAVE_PATTERN_TWILL, 3, 1), inclination, 0.5f), 32);
  ASSERT_EQ(tile.yarns.size(), 8u);  // 4 warps, then 4 wefts
  EXPECT_EQ(tile.model_to_tile, glm::vec3(0.25f));
  const float crimp = std::tan(inclination * std::numbers::pi_v<float> / 180.0f) / 3.0f;
  // Warp 0 is over wefts 0..2 and under weft 3: it rests at ±crimp on each crossing.
  const PeriodicYarn& warp = tile.yarns[0];
  EXPECT_EQ(warp.period, glm::vec3(0, 4, 0));
  for (int cross = 0; cross < 4; ++cross) {
    const glm::vec3 p = warp.points[cross * 32];
    EXPECT_FLOAT_EQ(p.x, 0.5f);
    EXPECT_FLOAT_EQ(p.y, cross + 0.5f);
    EXPECT_NEAR(p.z, cross < 3 ? crimp : -crimp, 1e-6f);
  }
  float steepest = 0.0f;
  for (const glm::vec3& t : warp.tangents) steepest = std::max(steepest, std::abs(t.z) / std::abs(t.y));
  EXPECT_NEAR(std::atan(steepest) * 180.0f / std::numbers::pi_v<float>, inclination, 0.1f);
  // Weft 3 is over warp 0 exactly where warp 0 is under it.
  EXPECT_NEAR(tile.yarns[4 + 3].points[0].z, crimp, 1e-6f);
}

TEST(WovenTile, GapSetsTheWidthAndThicknessIsCappedByRadiusAndCrimp) {
  const TileYarns thin = BuildWovenYarns(With(WovenSpec(v1::WEAVE_PATTERN_PLAIN, 0, 0, 0.3f), 60.0f, 0.05f), 4);
  EXPECT_EQ(thin.yarns[0].shape, SectionShape::kLens);
  EXPECT_FLOAT_EQ(thin.yarns[0].section[0].x, 0.35f);
  EXPECT_FLOAT_EQ(thin.yarns[0].section[0].y, 0.05f);  // the radius fits
  const TileYarns thick = BuildWovenYarns(With(WovenSpec(v1::WEAVE_PATTERN_PLAIN), 20.0f, 0.5f), 4);
  const float radians = 20.0f * std::numbers::pi_v<float> / 180.0f;
  EXPECT_FLOAT_EQ(thick.yarns[0].section[0].y, std::tan(radians) / 3 * std::cos(radians) / kWovenCrimpClearance);
}

}  // namespace
}  // namespace loom
