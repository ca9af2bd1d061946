#include "core/fabric/knit_tile.h"

#include <gtest/gtest.h>

#include "core/spec/defaults.h"
#include "fabric_specs.h"
#include "yarn_clearance.h"

namespace loom {
namespace {

// Yarns may come this close to touching (2% of the radius).
constexpr float kTolerance = 0.02f;
constexpr int kDenseSamples = 16;

// The pattern's tile enlarged to at least 2 wales and 3 courses, so that the 3×3
// neighbourhood of tiles compares every course with the courses two above and below
// (the head of one loop reaches up towards the sinker two courses higher).
v1::FabricSpec Enlarged(v1::FabricSpec fabric, float aspect) {
  fabric.mutable_knit()->set_loop_aspect(aspect);
  const v1::KnitSpec knit = WithDefaults(fabric).knit();
  uint32_t courses = knit.courses();
  while (courses < 3) courses += knit.courses();
  fabric.mutable_knit()->set_courses(courses);
  fabric.mutable_knit()->set_wales(knit.wales() < 2 ? 2 * knit.wales() : knit.wales());
  return WithDefaults(fabric);
}

TEST(KnitTile, YarnsNeverInterpenetrate) {
  for (const float aspect : {0.5f, 0.8f, 1.25f, 1.7f, 2.0f}) {
    for (const float radius : {0.02f, 0.05f, kMaxKnitYarnRadius}) {
      for (const NamedFabric& fabric : KnitFabrics(radius)) {
        const TileYarns tile = BuildKnitYarns(Enlarged(fabric.spec, aspect), kDenseSamples);
        const Clearance clearance = MeasureClearance(tile);
        EXPECT_GE(clearance.ratio, 1.0f - kTolerance)
            << fabric.name << " aspect " << aspect << " radius " << radius << " near (" << clearance.where.x << ", "
            << clearance.where.y << ", " << clearance.where.z << ")";
        // A tube bent tighter than its radius folds over itself.
        EXPECT_GE(MinCurvatureRatio(tile), 1.0f - kTolerance) << fabric.name << " aspect " << aspect;
      }
    }
  }
}

// The validator's jitter cap holds the clearance at the thickest yarn it allows.
TEST(KnitTile, LargestJitterKeepsTheThickestYarnsApart) {
  for (const float aspect : {kMinLoopAspect, 1.25f, kMaxLoopAspect}) {
    for (const uint64_t seed : {1u, 2u, 3u}) {
      for (const NamedFabric& fabric : KnitFabrics(kMaxKnitYarnRadius)) {
        v1::FabricSpec jittered = Enlarged(fabric.spec, aspect);
        jittered.mutable_knit()->set_loop_jitter(kMaxLoopJitter);
        jittered.mutable_knit()->set_seed(seed);
        const Clearance clearance = MeasureClearance(BuildKnitYarns(jittered, kDenseSamples));
        EXPECT_GE(clearance.ratio, 1.0f - kTolerance) << fabric.name << " aspect " << aspect << " seed " << seed;
      }
    }
  }
}

TEST(KnitTile, CoursesSpanOnePeriodAndTheTileHasItsLoopCount) {
  v1::FabricSpec fabric = KnitSpec(v1::KNIT_PATTERN_SEED, 0.08f);
  fabric.mutable_knit()->set_wales(4);
  fabric.mutable_knit()->set_courses(6);
  const TileYarns tile = BuildKnitYarns(WithDefaults(fabric), 4);
  ASSERT_EQ(tile.yarns.size(), 6u);  // one yarn per course
  for (const PeriodicYarn& yarn : tile.yarns) {
    EXPECT_EQ(yarn.period, glm::vec3(4, 0, 0));
    EXPECT_EQ(yarn.points.back(), yarn.points.front() + yarn.period);
    EXPECT_EQ(yarn.points.size(), 4u * 7 * 4 + 1);  // 7 key points per loop
  }
  // Four loop widths across and six loop heights up fill the unit tile.
  const float h = 1.0f / WithDefaults(fabric).knit().loop_aspect();
  EXPECT_FLOAT_EQ(tile.model_to_tile.x, 0.25f);
  EXPECT_FLOAT_EQ(tile.model_to_tile.y, 1.0f / (6 * h));
  EXPECT_FLOAT_EQ(tile.model_to_tile.z, 0.25f);
}

TEST(KnitTile, PurlIsKnitMirroredInDepth) {
  const TileYarns knit = BuildKnitYarns(WithDefaults(KnitSpec(v1::KNIT_PATTERN_STOCKINETTE, 0.08f)), 4);
  const TileYarns purl = BuildKnitYarns(WithDefaults(KnitSpec(v1::KNIT_PATTERN_REVERSE, 0.08f)), 4);
  ASSERT_EQ(knit.yarns[0].points.size(), purl.yarns[0].points.size());
  for (size_t i = 0; i < knit.yarns[0].points.size(); ++i) {
    const glm::vec3 k = knit.yarns[0].points[i], p = purl.yarns[0].points[i];
    EXPECT_FLOAT_EQ(k.x, p.x);
    EXPECT_FLOAT_EQ(k.y, p.y);
    EXPECT_FLOAT_EQ(k.z, -p.z);
  }
}

TEST(KnitTile, ColourPatternPicksTheYarnOfEachLoop) {
  v1::FabricSpec fabric = KnitSpec(v1::KNIT_PATTERN_STOCKINETTE, 0.08f);
  fabric.add_yarns()->set_radius(0.05f);
  fabric.mutable_knit()->set_wales(3);
  fabric.mutable_knit()->set_courses(2);
  for (const uint32_t yarn : {0u, 1u}) fabric.mutable_knit()->add_colour_pattern(yarn);  // repeats: 0 1 0 / 1 0 1
  const TileYarns tile = BuildKnitYarns(WithDefaults(fabric), 2);
  const size_t per_loop = 7 * 2;
  for (uint32_t course = 0; course < 2; ++course) {
    const PeriodicYarn& yarn = tile.yarns[course];
    for (uint32_t wale = 0; wale < 3; ++wale) {
      const uint32_t expected = (course * 3 + wale) % 2;
      EXPECT_EQ(yarn.segment_yarn[wale * per_loop], expected);
      EXPECT_EQ(yarn.segment_yarn[(wale + 1) * per_loop - 1], expected);
      EXPECT_FLOAT_EQ(yarn.section[wale * per_loop + 1].x, expected == 0 ? 0.08f : 0.05f);
    }
  }
}

}  // namespace
}  // namespace loom
