#include "core/acquire/acquisition.h"
#include "core/acquire/hemisphere_directions.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <stdexcept>
#include <thread>

#include "core/acquire/fibre_microflake_brdf.h"
#include "core/fabric/fabric_tile.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "tests/core/acquire/test_tiles.h"

namespace loom {
namespace {

using testing::Axis;
using testing::FlatPatch;
using testing::Lambertian;
using testing::Merge;
using testing::Tube;
using testing::Tubes;

v1::PrecomputeSettings Settings(uint32_t resolution, uint32_t views, uint32_t lights, uint32_t bounces,
                                uint32_t supersampling = 2) {
  v1::PrecomputeSettings settings;
  settings.set_spatial_resolution(resolution);
  settings.set_view_directions(views);
  settings.set_light_directions(lights);
  settings.set_indirect_bounces(bounces);
  settings.set_supersampling(supersampling);
  settings.set_seed(1234);
  return settings;
}

void ExpectAllFinite(const RadianceSamples& s) {
  for (float a : s.alpha) ASSERT_TRUE(std::isfinite(a) && a >= 0.0f && a <= 1.0f);
  for (const glm::vec3& r : s.radiance) ASSERT_TRUE(std::isfinite(r.r) && std::isfinite(r.g) && std::isfinite(r.b));
  for (const glm::vec3& n : s.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (const glm::vec3& t : s.tangents) ASSERT_NEAR(glm::length(t), 1.0f, 1e-5f);
}

// The message of the Error(kInvalidArgument) Acquire throws; fails if it calls
// progress first (validation must come before any work).
std::string AcquireError(const FabricTile& tile, const v1::PrecomputeSettings& settings) {
  bool progressed = false;
  try {
    Acquire(tile, settings, [&](double, std::string_view) { progressed = true; });
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_FALSE(progressed);
    return error.what();
  }
  ADD_FAILURE() << "Acquire did not fail";
  return {};
}

// --- Radiance of a flat patch ------------------------------------------------------------

TEST(Acquisition, WhiteLambertianFlatPatchHasRadianceAlbedoOverPiTimesCosine) {
  const FabricTile patch = FlatPatch(0.25f, Lambertian(1.0f));
  for (uint32_t bounces : {0u, 1u}) {  // a flat patch has no inter-reflection
    const RadianceSamples s = Acquire(patch, Settings(4, 9, 9, bounces));
    ExpectAllFinite(s);
    for (size_t texel = 0; texel < s.texel_count(); ++texel) {
      EXPECT_EQ(s.normals[texel], glm::vec3(0, 0, 1));
      EXPECT_EQ(s.tangents[texel], glm::vec3(1, 0, 0));
      for (size_t view = 0; view < s.view_count(); ++view) {
        EXPECT_EQ(s.alpha[s.AlphaIndex(texel, view)], 1.0f);
        for (size_t light = 0; light < s.light_count(); ++light) {
          const float expected = glm::one_over_pi<float>() * s.light_directions[light].z;
          const glm::vec3 radiance = s.radiance[s.RadianceIndex(texel, view, light)];
          EXPECT_NEAR(radiance.r, expected, 0.01f * expected) << bounces << " " << texel << " " << view << " " << light;
          EXPECT_EQ(radiance.r, radiance.g);
        }
      }
      // Light 4 of a 3×3 grid is the zenith: exactly 1/π.
      EXPECT_NEAR(s.radiance[s.RadianceIndex(texel, 4, 4)].r, glm::one_over_pi<float>(), 0.01f / glm::pi<float>());
    }
  }
}

TEST(Acquisition, FlatPatchInTheMicroflakeModelHasRadianceItsBrdfTimesCosine) {
  // The yarn's model reaches acquisition: a flat patch of microflake yarn along x.
  YarnMaterial material;
  material.model = YarnShadingModel::kMicroflake;
  material.diffuse_albedo = glm::vec3(0.3f);
  material.specular_albedo = glm::vec3(0.6f);
  material.roughness = 0.3f;
  const FabricTile patch = FlatPatch(0.25f, material);
  const FibreMicroflakeBrdf brdf(material);
  const RadianceSamples s = Acquire(patch, Settings(4, 16, 16, 0));
  float largest_specular = 0.0f;
  for (size_t view = 0; view < s.view_count(); ++view) {
    for (size_t light = 0; light < s.light_count(); ++light) {
      const glm::vec3 l = s.light_directions[light], v = s.view_directions[view];
      const float expected = brdf.Evaluate({0, 0, 1}, {1, 0, 0}, l, v).r * l.z;
      const float radiance = s.radiance[s.RadianceIndex(0, view, light)].r;
      EXPECT_NEAR(radiance, expected, 1e-3f * expected) << view << " " << light;
      largest_specular = std::max(largest_specular, expected - 0.3f / glm::pi<float>() * l.z);
    }
  }
  EXPECT_GT(largest_specular, 0.05f);  // the specular term is there to be seen
}

TEST(Acquisition, FlatMicroflakePatchLitFromBehindHasRadianceItsBtdfTimesCosine) {
  // Lights below the cloth (LightSide::kBack): the grid mirrored, and what reaches
  // the top of an open patch is its transmission; a Kajiya-Kay patch stays black.
  YarnMaterial material;
  material.model = YarnShadingModel::kMicroflake;
  material.diffuse_albedo = glm::vec3(0.4f);
  material.specular_albedo = glm::vec3(0.5f);
  material.roughness = 0.3f;
  material.diffuse_transmission = 0.5f;
  const FibreMicroflakeBrdf brdf(material);
  const RadianceSamples s = Acquire(FlatPatch(0.25f, material), Settings(4, 16, 16, 0), {}, nullptr, {}, LightSide::kBack);
  const std::vector<glm::vec3> grid = HemisphereGridDirections(16);
  float largest_specular = 0.0f;
  for (size_t light = 0; light < s.light_count(); ++light) {
    const glm::vec3 l = s.light_directions[light];
    ASSERT_EQ(l, glm::vec3(grid[light].x, grid[light].y, -grid[light].z));
    for (size_t view = 0; view < s.view_count(); ++view) {
      const glm::vec3 v = s.view_directions[view];
      const float expected = brdf.Transmit({0, 0, 1}, {1, 0, 0}, l, v).r * -l.z;
      EXPECT_NEAR(s.radiance[s.RadianceIndex(0, view, light)].r, expected, 1e-3f * expected) << view << " " << light;
      largest_specular = std::max(largest_specular, expected - 0.2f / glm::pi<float>() * -l.z);
    }
  }
  EXPECT_GT(largest_specular, 0.02f);
  const RadianceSamples opaque = Acquire(FlatPatch(0.25f, Lambertian(0.7f)), Settings(4, 16, 16, 0), {}, nullptr, {},
                                         LightSide::kBack);
  for (const glm::vec3& radiance : opaque.radiance) EXPECT_EQ(radiance, glm::vec3(0.0f));
}

// --- Holes -----------------------------------------------------------------------------------

TEST(Acquisition, AlphaIsZeroExactlyWhereTheViewPassesThroughAHoleToNothing) {
  // Two yarns along x at y = 0.25 and 0.75 (radius 0.1): gaps over y ∈ (0.35, 0.65)
  // and (0.85, 1.15). Texel rows of 1/16: rows 6-9 and 14-1 lie over gaps, rows 3-4
  // and 11-12 over yarn.
  const FabricTile tile = Tubes({{Axis::kX, 0.25f, 0.5f, 0.1f}, {Axis::kX, 0.75f, 0.5f, 0.1f}}, Lambertian(0.7f));
  const RadianceSamples s = Acquire(tile, Settings(16, 9, 4, 1));
  ExpectAllFinite(s);
  // View 4 is the zenith; views 3 and 5 tilt towards −x and +x, along the yarns,
  // so the gaps stay open.
  for (size_t view : {3u, 4u, 5u}) {
    for (uint32_t y = 0; y < 16; ++y) {
      const bool gap = (y >= 6 && y <= 9) || y >= 14 || y <= 1;
      const bool yarn = y == 3 || y == 4 || y == 11 || y == 12;
      for (uint32_t x = 0; x < 16; ++x) {
        const size_t texel = y * 16 + x;
        const float alpha = s.alpha[s.AlphaIndex(texel, view)];
        if (gap) {
          EXPECT_EQ(alpha, 0.0f) << "view " << view << " row " << y;
          for (size_t light = 0; light < s.light_count(); ++light) {
            EXPECT_EQ(s.radiance[s.RadianceIndex(texel, view, light)], glm::vec3(0.0f));
          }
        }
        if (yarn) {
          EXPECT_EQ(alpha, 1.0f) << "view " << view << " row " << y;
        }
      }
    }
  }
  // Seen from a view tilted across the yarns (+y, view 7), the gaps close partly.
  EXPECT_GT(s.alpha[s.AlphaIndex(8 * 16, 7)] + s.alpha[s.AlphaIndex(7 * 16, 7)], 0.0f);
}

// --- Shadows ---------------------------------------------------------------------------------

// The fraction of floor points y ∈ [y0, y1] (z = 0) that a tube along x at
// (y = 0.5, z = height) of radius r and its periodic copies shadow from light l.
float ExpectedShadowedFraction(float y0, float y1, glm::vec3 l, float height, float r) {
  const glm::vec2 d = glm::normalize(glm::vec2(l.y, l.z));
  int shadowed = 0, total = 0;
  for (float y = y0; y < y1; y += 1e-3f, ++total) {
    for (int k = -8; k <= 8; ++k) {
      const glm::vec2 centre(0.5f + k, height);
      const glm::vec2 to_centre = centre - glm::vec2(y, 0.0f);
      const float along = glm::dot(to_centre, d);
      const float distance = std::abs(to_centre.x * d.y - to_centre.y * d.x);
      if (along > 0.0f && distance <= r) {
        ++shadowed;
        break;
      }
    }
  }
  return static_cast<float>(shadowed) / total;
}

// The issue's case on real geometry: a single-layer plain weave with gaps, seen
// head-on, is a hole (alpha exactly 0, radiance 0) wherever the view passes
// through a gap, and covered over the threads.
TEST(Acquisition, SingleLayerWeaveSeenHeadOnShowsItsGapsAsAlphaZero) {
  const FabricTile tile = BuildFabricTile(
      ParseSpecJson<v1::FabricSpec>(R"({"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "gap_ratio": 0.3}})", "fabric"));
  v1::PrecomputeSettings settings;
  settings.set_spatial_resolution(32);
  settings.set_view_directions(9);  // 3×3: direction 4 is the zenith
  settings.set_light_directions(4);
  const RadianceSamples samples = Acquire(tile, settings);
  constexpr size_t kZenith = 4;
  ASSERT_NEAR(samples.view_directions[kZenith].z, 1.0f, 1e-6f);
  size_t holes = 0, covered = 0;
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    const float alpha = samples.alpha[samples.AlphaIndex(texel, kZenith)];
    if (alpha == 0.0f) {
      ++holes;
      for (size_t light = 0; light < samples.light_count(); ++light) {
        EXPECT_EQ(samples.radiance[samples.RadianceIndex(texel, kZenith, light)], glm::vec3(0.0f));
      }
    }
    if (alpha == 1.0f) ++covered;
  }
  // The tile holds 2×2 gaps of 0.3 of a 0.5 pitch, 4.8 texels wide: about 9% of the
  // area is open; the texels wholly inside a gap (≈ 4 × 3.8²) must be holes.
  EXPECT_GT(holes, 40u);
  EXPECT_LT(holes, 110u);
  EXPECT_GT(covered, 800u);
  // Without gaps nothing is a hole.
  const FabricTile closed = BuildFabricTile(
      ParseSpecJson<v1::FabricSpec>(R"({"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "gap_ratio": 0}})", "fabric"));
  const RadianceSamples closed_samples = Acquire(closed, settings);
  for (size_t texel = 0; texel < closed_samples.texel_count(); ++texel) {
    EXPECT_GT(closed_samples.alpha[closed_samples.AlphaIndex(texel, kZenith)], 0.0f) << texel;
  }
}

TEST(Acquisition, ShadowedFractionRisesAsTheLightGoesGrazing) {
  // A floor under a yarn along x (y = 0.5, z = 0.4, r = 0.1), seen from the zenith;
  // lights in the y-z plane from the zenith to 78°. The floor's radiance divided
  // by its unshadowed value ρ/π·cos θ is its lit fraction.
  const float albedo = 0.8f;
  const FabricTile tile = Merge(FlatPatch(0.0f, Lambertian(albedo)), Tubes({{Axis::kX, 0.5f, 0.4f, 0.1f}}, Lambertian(albedo)));
  const RadianceSamples s = Acquire(tile, Settings(32, 9, 81, 0));
  ExpectAllFinite(s);
  const size_t zenith_view = 4;
  float previous = -1.0f;
  for (uint32_t row = 4; row <= 8; ++row) {  // column 4 of the 9×9 light grid: +y
    const size_t light = row * 9 + 4;
    const glm::vec3 l = s.light_directions[light];
    double lit = 0.0;
    int count = 0;
    for (uint32_t y = 0; y < 32; ++y) {
      if (y >= 12 && y < 20) continue;  // under the yarn: the view sees the yarn there
      for (uint32_t x = 0; x < 32; ++x, ++count) {
        lit += s.radiance[s.RadianceIndex(y * 32 + x, zenith_view, light)].r / (albedo / glm::pi<float>() * l.z);
      }
    }
    const float shadowed = 1.0f - static_cast<float>(lit / count);
    const float expected = (ExpectedShadowedFraction(0.0f, 0.375f, l, 0.4f, 0.1f) * 0.375f +
                            ExpectedShadowedFraction(0.625f, 1.0f, l, 0.4f, 0.1f) * 0.375f) / 0.75f;
    EXPECT_NEAR(shadowed, expected, 0.04f) << "light at " << glm::degrees(std::acos(l.z)) << "°";
    EXPECT_GE(shadowed, previous) << "light at " << glm::degrees(std::acos(l.z)) << "°";
    previous = shadowed;
  }
  EXPECT_GT(previous, 0.8f);  // at 78° the shadow spans most of the period
}

// --- Indirect light --------------------------------------------------------------------------

TEST(Acquisition, EveryBounceAddsLightAndNothingElseChanges) {
  const FabricTile tile = Merge(FlatPatch(0.0f, Lambertian(0.9f)), Tubes({{Axis::kX, 0.5f, 0.12f, 0.1f}}, Lambertian(0.9f)));
  const RadianceSamples none = Acquire(tile, Settings(8, 4, 4, 0));
  const RadianceSamples one = Acquire(tile, Settings(8, 4, 4, 1));
  const RadianceSamples two = Acquire(tile, Settings(8, 4, 4, 2));
  EXPECT_EQ(one.alpha, none.alpha);
  EXPECT_EQ(one.normals, none.normals);
  double added_one = 0.0, added_two = 0.0;
  for (size_t i = 0; i < none.radiance.size(); ++i) {
    ASSERT_GE(one.radiance[i].r, none.radiance[i].r * (1 - 1e-6f));
    ASSERT_GE(two.radiance[i].r, one.radiance[i].r * (1 - 1e-6f));
    added_one += one.radiance[i].r - none.radiance[i].r;
    added_two += two.radiance[i].r - one.radiance[i].r;
  }
  EXPECT_GT(added_one, 0.0);
  EXPECT_GT(added_two, 0.0);
  EXPECT_LT(added_two, added_one);  // each bounce is weaker (albedo < 1)
}

TEST(Acquisition, OneBounceInVGroovesMatchesTheFacetViewFactor) {
  // 90° V-grooves lit and seen from the zenith: each facet gets E₀ = cos 45° and
  // sees the opposite facet with view factor F = 1 − sin 45° (Hottel's crossed
  // strings), so one bounce adds ρ/π · ρ · E₀ · F on average.
  const float albedo = 0.8f;
  const FabricTile tile = testing::VGrooves(Lambertian(albedo), 48);
  const RadianceSamples direct = Acquire(tile, Settings(32, 9, 9, 0));
  const RadianceSamples bounced = Acquire(tile, Settings(32, 9, 9, 1));
  const size_t zenith = 4;
  double added = 0.0;
  for (size_t texel = 0; texel < direct.texel_count(); ++texel) {
    const size_t i = direct.RadianceIndex(texel, zenith, zenith);
    EXPECT_NEAR(direct.radiance[i].r, albedo / glm::pi<float>() * std::sqrt(0.5f), 1e-5f);
    added += bounced.radiance[i].r - direct.radiance[i].r;
  }
  added /= static_cast<double>(direct.texel_count());
  const double expected = albedo / glm::pi<double>() * albedo * std::sqrt(0.5) * (1 - std::sqrt(0.5));
  EXPECT_NEAR(added, expected, 0.02 * expected);
}

// --- Normals and tangents ----------------------------------------------------------------------

TEST(Acquisition, TexelTangentIsPerpendicularToTheNormalInThePlaneOfNormalAndX) {
  const FabricTile tile = Tubes({{Axis::kY, 0.3f, 0.2f, 0.15f}, {Axis::kX, 0.7f, 0.4f, 0.1f}}, Lambertian(0.5f));
  const RadianceSamples s = Acquire(tile, Settings(8, 16, 4, 0));
  ExpectAllFinite(s);
  const glm::vec3 x(1, 0, 0);
  for (size_t texel = 0; texel < s.texel_count(); ++texel) {
    const glm::vec3 n = s.normals[texel], t = s.tangents[texel];
    EXPECT_NEAR(glm::dot(n, t), 0.0f, 1e-5f);
    EXPECT_GE(glm::dot(t, x), 0.0f);
    EXPECT_NEAR(glm::dot(t, glm::cross(n, x)), 0.0f, 1e-5f);
    EXPECT_GT(n.z, 0.0f);  // averaged over the views, normals lean up
  }
}

// --- Determinism -------------------------------------------------------------------------------

FabricTile SmallWeave() {
  YarnMaterial material;
  material.diffuse_albedo = {0.6f, 0.3f, 0.2f};
  material.specular_albedo = glm::vec3(0.1f);
  material.specular_exponent = 40.0f;
  std::vector<Tube> tubes;
  for (int i = 0; i < 4; ++i) {
    tubes.push_back({Axis::kX, (i + 0.5f) / 4, 0.16f, 0.05f});
    tubes.push_back({Axis::kY, (i + 0.5f) / 4, 0.05f, 0.05f});
  }
  return Tubes(tubes, material, 16, 8);
}

// --- Sampling planes ----------------------------------------------------------------------

// A tube along x (axis at y = ½, z = ½, radius r) over nothing: a view's texels
// cover the tube's silhouette, whose centre is where the axis projects along the
// view onto the view's plane, y = ½ + (v.y / v.z)(h(v) − ½). Seen from the zenith
// the rays meet the tube at a mean height of ½ + πr/4 (the mean of √(r² − y²)).
TEST(Acquisition, EachViewsTexelsLieOnItsSamplingPlane) {
  const float r = 0.05f;
  const FabricTile tile = Tubes({{Axis::kX, 0.5f, 0.5f, r}}, Lambertian(0.7f), 64);
  for (const auto plane : {v1::SAMPLING_PLANE_TOP, v1::SAMPLING_PLANE_VIEW_DEPTH}) {
    SCOPED_TRACE(v1::SamplingPlane_Name(plane));
    auto settings = Settings(64, 25, 4, 0, 2);
    settings.set_sampling_plane(plane);
    const RadianceSamples s = Acquire(tile, settings);
    ASSERT_EQ(s.view_heights.size(), 25u);
    const glm::vec3 zenith = s.view_directions[12];
    ASSERT_EQ(zenith, glm::vec3(0, 0, 1));
    if (plane == v1::SAMPLING_PLANE_TOP) {
      for (float h : s.view_heights) EXPECT_NEAR(h, tile.z_max, 1e-3f);
    } else {
      EXPECT_NEAR(s.view_heights[12], 0.5f + glm::pi<float>() * r / 4.0f, 2e-3f);
      for (float h : s.view_heights) {
        EXPECT_GT(h, 0.5f);
        EXPECT_LE(h, tile.z_max + 1e-3f);
      }
    }
    for (size_t view = 0; view < s.view_count(); ++view) {
      const glm::vec3 v = s.view_directions[view];
      // The silhouette's centre in y: a circular mean over the texel rows (it may wrap).
      glm::dvec2 sum(0.0);
      for (size_t texel = 0; texel < s.texel_count(); ++texel) {
        const double angle = 2.0 * glm::pi<double>() * ((texel / 64) + 0.5) / 64.0;
        sum += double{s.alpha[s.AlphaIndex(texel, view)]} * glm::dvec2(std::cos(angle), std::sin(angle));
      }
      const double centre = std::atan2(sum.y, sum.x) / (2.0 * glm::pi<double>());
      const double expected = 0.5 + double{v.y / v.z} * (double{s.view_heights[view]} - 0.5);
      const double error = std::remainder(centre - expected, 1.0);
      EXPECT_LT(std::abs(error), 0.5 / 64.0) << "view " << view << " centre " << centre << " expected " << expected;
    }
  }
}

TEST(Acquisition, SameInputsGiveBitIdenticalSamplesWhateverTheThreadCount) {
  const FabricTile tile = SmallWeave();
  auto settings = Settings(8, 9, 4, 1, 3);
  settings.set_sampling_plane(v1::SAMPLING_PLANE_VIEW_DEPTH);
  const std::string first = EncodeRadianceSamples(Acquire(tile, settings, {}, nullptr, {.threads = 2}));
  const std::string second = EncodeRadianceSamples(Acquire(tile, settings, {}, nullptr, {.threads = 2}));
  const std::string single = EncodeRadianceSamples(Acquire(tile, settings, {}, nullptr, {.threads = 1}));
  EXPECT_TRUE(first == second);
  EXPECT_TRUE(first == single);
  // The seed matters (jitter and gather directions).
  auto reseeded = settings;
  reseeded.set_seed(99);
  EXPECT_FALSE(first == EncodeRadianceSamples(Acquire(tile, reseeded, {}, nullptr, {.threads = 2})));
}

// The rays sit on one grid over the tile: 4 texels of 4×4 rays and 8 texels of
// 2×2 cast the same 16×16 rays, so a coarse texel's samples (coverage-weighted
// means of its children, as fabric_fit pools them) and hit normals do not depend
// on the resolution they were acquired at.
TEST(Acquisition, ResolutionsWithTheSameRaysPerTileSidePoolToTheSameSamples) {
  const FabricTile tile = SmallWeave();
  const RadianceSamples coarse = Acquire(tile, Settings(4, 9, 4, 0, 4));
  const RadianceSamples fine = Acquire(tile, Settings(8, 9, 4, 0, 2));
  size_t compared = 0;
  for (size_t texel = 0; texel < coarse.texel_count(); ++texel) {
    const size_t x = texel % 4, y = texel / 4;
    const std::array<size_t, 4> children = {2 * y * 8 + 2 * x, 2 * y * 8 + 2 * x + 1, (2 * y + 1) * 8 + 2 * x,
                                            (2 * y + 1) * 8 + 2 * x + 1};
    glm::dvec3 normal_sum(0.0), coarse_normal_sum(0.0);
    for (size_t v = 0; v < coarse.view_count(); ++v) {
      double coverage = 0.0;
      for (size_t child : children) coverage += fine.alpha[fine.AlphaIndex(child, v)];
      ASSERT_FLOAT_EQ(coarse.alpha[coarse.AlphaIndex(texel, v)], float(coverage / 4)) << "texel " << texel << " view " << v;
      if (coverage == 0.0) continue;
      for (size_t l = 0; l < coarse.light_count(); ++l) {
        glm::dvec3 pooled(0.0);
        for (size_t child : children) {
          pooled += double{fine.alpha[fine.AlphaIndex(child, v)]} * glm::dvec3(fine.radiance[fine.RadianceIndex(child, v, l)]);
        }
        pooled /= coverage;
        const glm::dvec3 direct(coarse.radiance[coarse.RadianceIndex(texel, v, l)]);
        ASSERT_LT(glm::length(pooled - direct), 1e-5 * (1.0 + glm::length(direct))) << "texel " << texel;
        ++compared;
      }
    }
    for (size_t child : children) {
      double coverage = 0.0;
      for (size_t v = 0; v < fine.view_count(); ++v) coverage += fine.alpha[fine.AlphaIndex(child, v)];
      normal_sum += glm::dvec3(fine.normals[child]) * double{fine.normal_lengths[child]} * coverage;
    }
    ASSERT_GE(coarse.normal_lengths[texel], 0.0f);
    ASSERT_LE(coarse.normal_lengths[texel], 1.0f);
    EXPECT_LT(glm::length(glm::normalize(normal_sum) - glm::dvec3(coarse.normals[texel])), 1e-5) << "texel " << texel;
  }
  EXPECT_GT(compared, 100u);
}

TEST(Acquisition, LightBatchesGiveTheSameSamplesAsOnePass) {
  // A memory budget for 5 lights' indirect irradiance splits 16 lights into 4 batches.
  const FabricTile tile = SmallWeave();
  const auto settings = Settings(4, 4, 16, 2);
  AcquireStats stats;
  const RadianceSamples whole = Acquire(tile, settings, {}, &stats);
  EXPECT_EQ(stats.light_batches, 1u);
  const size_t per_light = 3 * sizeof(glm::vec3) * tile.mesh.positions.size();
  const RadianceSamples batched = Acquire(tile, settings, {}, &stats, {.indirect_memory_bytes = 5 * per_light});
  EXPECT_EQ(stats.light_batches, 4u);
  EXPECT_TRUE(EncodeRadianceSamples(batched) == EncodeRadianceSamples(whole));
}

// --- Degenerate and bad input --------------------------------------------------------------------

TEST(Acquisition, DegenerateTilesGiveFiniteSamples) {
  // No geometry at all: nothing covers any texel.
  AcquireStats stats;
  const RadianceSamples empty = Acquire(FabricTile{}, Settings(4, 4, 4, 2), {}, &stats);
  ExpectAllFinite(empty);
  for (float a : empty.alpha) EXPECT_EQ(a, 0.0f);
  EXPECT_EQ(empty.normals[0], glm::vec3(0, 0, 1));
  EXPECT_EQ(stats.non_finite_values, 0u);

  // Zero normals and tangents, zero-area triangles, an extreme fibre exponent.
  YarnMaterial shiny;
  shiny.diffuse_albedo = glm::vec3(0.0f);
  shiny.specular_albedo = glm::vec3(1.0f);
  shiny.specular_exponent = 1e5f;
  FabricTile tile = FlatPatch(0.3f, shiny);
  tile.mesh.normals.assign(4, glm::vec3(0.0f));
  tile.mesh.tangents.assign(4, glm::vec4(0.0f));
  tile.mesh.positions.push_back({0.5f, 0.5f, 0.3f});
  tile.mesh.normals.push_back(glm::vec3(0.0f));
  tile.mesh.tangents.push_back(glm::vec4(0.0f));
  tile.mesh.indices.insert(tile.mesh.indices.end(), {0, 0, 0, 0, 4, 2});  // a point and a line
  tile.triangle_material.insert(tile.triangle_material.end(), {0, 0});
  const RadianceSamples s = Acquire(tile, Settings(4, 9, 9, 2), {}, &stats);
  ExpectAllFinite(s);
  EXPECT_EQ(stats.non_finite_values, 0u);
  for (float a : s.alpha) EXPECT_EQ(a, 1.0f);
}

TEST(Acquisition, SettingsPastTheCapsFailBeforeAnyWorkNamingTheField) {
  const FabricTile patch = FlatPatch(0.0f, Lambertian(0.5f));
  EXPECT_NE(AcquireError(patch, Settings(8, 5000, 4, 1)).find("precompute.view_directions"), std::string::npos);
  EXPECT_NE(AcquireError(patch, Settings(8, 10, 4, 1)).find("precompute.view_directions"), std::string::npos);
  EXPECT_NE(AcquireError(patch, Settings(8, 4, 4, 3)).find("precompute.indirect_bounces"), std::string::npos);
  EXPECT_NE(AcquireError(patch, Settings(8, 4, 4, 1, 9)).find("precompute.supersampling"), std::string::npos);
  EXPECT_NE(AcquireError(patch, Settings(256, 4096, 4096, 1)).find("radiance samples exceeds"), std::string::npos);
}

TEST(Acquisition, InconsistentTilesFailBeforeAnyWorkNamingTheField) {
  const auto settings = Settings(4, 4, 4, 1);
  FabricTile bad_index = FlatPatch(0.0f, Lambertian(0.5f));
  bad_index.mesh.indices[4] = 17;
  EXPECT_NE(AcquireError(bad_index, settings).find("tile.mesh.indices[4]"), std::string::npos);

  FabricTile bright = FlatPatch(0.0f, Lambertian(1.0f));
  bright.materials[0].specular_albedo = glm::vec3(0.5f);
  EXPECT_NE(AcquireError(bright, settings).find("tile.materials[0].diffuse_albedo"), std::string::npos);

  FabricTile above = FlatPatch(0.2f, Lambertian(0.5f));
  above.z_max = 0.1f;
  above.z_min = 0.0f;
  EXPECT_NE(AcquireError(above, settings).find("tile.mesh.positions[0]"), std::string::npos);

  FabricTile nan = FlatPatch(0.0f, Lambertian(0.5f));
  nan.mesh.normals[2].y = std::nanf("");
  EXPECT_NE(AcquireError(nan, settings).find("tile.mesh.normals[2]"), std::string::npos);

  FabricTile missing = FlatPatch(0.0f, Lambertian(0.5f));
  missing.mesh.tangents.clear();
  EXPECT_NE(AcquireError(missing, settings).find("tile.mesh.tangents"), std::string::npos);
}

// --- Progress -----------------------------------------------------------------------------------

TEST(Acquisition, ProgressRisesToOneOnTheCallingThreadAndThrowingCancels) {
  const FabricTile tile = SmallWeave();
  std::vector<double> fractions;
  std::vector<std::string> stages;
  const auto caller = std::this_thread::get_id();
  AcquireStats stats;
  Acquire(
      tile, Settings(8, 4, 4, 1),
      [&](double fraction, std::string_view stage) {
        EXPECT_EQ(std::this_thread::get_id(), caller);
        fractions.push_back(fraction);
        stages.emplace_back(stage);
      },
      &stats, {.threads = 2});
  ASSERT_GT(fractions.size(), 4u);
  for (size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
  EXPECT_GE(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_EQ(stages.back(), "done");
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.threads, 2u);

  EXPECT_THROW(Acquire(tile, Settings(8, 4, 4, 1),
                       [](double fraction, std::string_view) {
                         if (fraction > 0.3) throw std::runtime_error("cancelled");
                       }),
               std::runtime_error);
}

}  // namespace
}  // namespace loom
