// Eq. 10's yarn shadow (core/render/yarn_shadow.h): what lies under a yarn's centre line
// within its reach is darkened by T_y(d), nothing else.

#include "core/render/yarn_shadow.h"

#include <gtest/gtest.h>

#include "core/fabric/yarn_volume.h"

namespace loom {
namespace {

YarnSection Section() {
  v1::YarnSpec yarn;
  yarn.set_plies(2);
  yarn.set_fuzz(0.3f);
  return MakeYarnSection(yarn);
}

TEST(YarnShadow, ProfileFallsFromTheCentreToNothingAtTheReach) {
  const std::vector<float> profile = YarnShadowProfile(Section(), kYarnOpticalDensity);
  ASSERT_EQ(profile.size(), static_cast<size_t>(kYarnShadowProfileSamples));
  EXPECT_NEAR(profile.front(), 1.0f - kYarnShadowStrength, 1e-6f);
  EXPECT_NEAR(profile.back(), 1.0f, 1e-6f);
  // In the fuzz, outside the plies, it rises to 1; inside, the plies keep it low (off
  // the centre, where two plies touch, lower than at it).
  const YarnSection section = Section();
  for (size_t k = 1; k < profile.size(); ++k) {
    EXPECT_GE(profile[k], 0.0f) << k;
    const float d = section.extent() * static_cast<float>(k) / (kYarnShadowProfileSamples - 1);
    if (d > 1.0f) {
      EXPECT_GE(profile[k], profile[k - 1] - 1e-6f) << k;
    }
    if (d < 0.6f) {
      EXPECT_LT(profile[k], 0.3f) << k;
    }
  }
}

// A yarn along x at height 1 over short segments of other chains at height 0, lit from
// straight above: those within its reach of its centre line (in the light's view) get
// T_y(d), those beyond it and one above the yarn get 1, and a segment of the yarn's own
// chain next to it is left to the lumislice.
TEST(YarnShadow, DarkensExactlyWhatLiesUnderACentreLineWithinItsReach) {
  const YarnSection section = Section();
  YarnShadowProfiles profiles;
  profiles.profile = {YarnShadowProfile(section, kYarnOpticalDensity)};
  profiles.extent = {section.extent()};
  profiles.own_chain_radii = 4.0f;
  const float radius = 0.1f, reach = section.extent() * radius;
  std::vector<ShadowSegment> segments = {{{-1.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 1.0f}, radius, 0, 0, 0.0f}};
  std::vector<float> offsets;
  for (float y = -0.3f; y <= 0.3f; y += 0.01f) {
    offsets.push_back(y);
    segments.push_back({{0.0f, y, 0.0f}, {0.02f, y, 0.0f}, radius, 0, 1 + static_cast<uint32_t>(offsets.size()), 0.0f});
  }
  segments.push_back({{0.5f, 0.0f, 2.0f}, {0.52f, 0.0f, 2.0f}, radius, 0, 1000, 0.0f});  // above the yarn
  segments.push_back({{1.0f, 0.0f, 0.9f}, {1.1f, 0.0f, 0.9f}, radius, 0, 0, 0.8f});     // its own chain, next to it
  const std::vector<float> shadow = YarnShadows(segments, profiles, SceneLight{true, {0.0f, 0.0f, 1.0f}});
  int darkened = 0;
  for (size_t k = 0; k < offsets.size(); ++k) {
    const float d = std::abs(offsets[k]) / radius;  // the segment's midpoint is right under the line
    const float t = shadow[k + 1];
    if (std::abs(offsets[k]) >= reach) {
      EXPECT_EQ(t, 1.0f) << offsets[k];
    } else {
      const float x = d / section.extent() * (kYarnShadowProfileSamples - 1);
      const int i = std::min(static_cast<int>(x), kYarnShadowProfileSamples - 2);
      EXPECT_NEAR(t, glm::mix(profiles.profile[0][i], profiles.profile[0][i + 1], x - i), 1e-5f) << offsets[k];
      EXPECT_LT(t, 1.0f) << offsets[k];
      ++darkened;
    }
  }
  EXPECT_GT(darkened, 20);
  EXPECT_EQ(shadow[offsets.size() + 1], 1.0f);  // above the yarn
  EXPECT_EQ(shadow[offsets.size() + 2], 1.0f);  // its own chain
  EXPECT_EQ(shadow[0], 1.0f);                   // the yarn itself: nothing above it
}

// A point light 2 above the yarn, itself 1 above the shaded segments: the ray from a
// segment's midpoint (0, y, 0) to the light passes the yarn's centre line 2|y|/3 from it,
// so the shadow is 1.5× as wide as a directional light's, and T_y is taken at that
// distance.
TEST(YarnShadow, PointLightsCastTheShadowOfTheirRays) {
  const YarnSection section = Section();
  YarnShadowProfiles profiles;
  profiles.profile = {YarnShadowProfile(section, kYarnOpticalDensity)};
  profiles.extent = {section.extent()};
  const float radius = 0.1f, reach = section.extent() * radius;
  std::vector<ShadowSegment> segments = {{{-1.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 1.0f}, radius, 0, 0, 0.0f}};
  std::vector<float> offsets;
  for (int k = -30; k <= 30; ++k) {
    offsets.push_back(0.01f * static_cast<float>(k));
    segments.push_back({{-0.01f, offsets.back(), 0.0f}, {0.01f, offsets.back(), 0.0f}, radius, 0,
                        1 + static_cast<uint32_t>(offsets.size()), 0.0f});
  }
  const std::vector<float> shadow = YarnShadows(segments, profiles, SceneLight{false, {0.0f, 0.0f, 3.0f}});
  int wider_than_directional = 0;
  for (size_t k = 0; k < offsets.size(); ++k) {
    const float d = 2.0f / 3.0f * std::abs(offsets[k]);
    const float t = shadow[k + 1];
    if (d >= reach * 0.999f) {
      EXPECT_EQ(t, 1.0f) << offsets[k];
    } else if (d <= reach * 0.998f) {
      const float x = d / radius / section.extent() * (kYarnShadowProfileSamples - 1);
      const int i = std::min(static_cast<int>(x), kYarnShadowProfileSamples - 2);
      EXPECT_NEAR(t, glm::mix(profiles.profile[0][i], profiles.profile[0][i + 1], x - i), 1e-4f) << offsets[k];
      if (std::abs(offsets[k]) > reach) ++wider_than_directional;
    }
  }
  EXPECT_GT(wider_than_directional, 4);
}

}  // namespace
}  // namespace loom
