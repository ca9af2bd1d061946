#include "core/fabric/fabric_tile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "core/acquire/kajiya_kay_brdf.h"
#include "core/fabric/knit_tile.h"
#include "core/fabric/yarn_material.h"
#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "fabric_specs.h"

namespace loom {
namespace {

std::vector<NamedFabric> AllFabrics() {
  std::vector<NamedFabric> all = KnitFabrics(kMaxKnitYarnRadius);
  for (NamedFabric& woven : WovenFabrics(0.2f)) all.push_back(std::move(woven));
  return all;
}

bool Finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Vertices at the same position (within 1e-6) share one id: the seam of each ring
// then disappears and the mesh's boundary is the open rings at the ends of the yarns.
std::vector<size_t> Weld(const std::vector<glm::vec3>& positions) {
  std::map<std::tuple<long, long, long>, std::vector<size_t>> cells;
  std::vector<size_t> id(positions.size());
  auto cell = [](glm::vec3 p) {
    return std::tuple<long, long, long>(std::lround(p.x * 1e4), std::lround(p.y * 1e4), std::lround(p.z * 1e4));
  };
  for (size_t i = 0; i < positions.size(); ++i) {
    id[i] = i;
    const auto [cx, cy, cz] = cell(positions[i]);
    for (long dx = -1; dx <= 1 && id[i] == i; ++dx)
      for (long dy = -1; dy <= 1 && id[i] == i; ++dy)
        for (long dz = -1; dz <= 1 && id[i] == i; ++dz) {
          const auto found = cells.find({cx + dx, cy + dy, cz + dz});
          if (found == cells.end()) continue;
          for (size_t j : found->second) {
            if (glm::distance(positions[i], positions[j]) < 1e-6f) {
              id[i] = id[j];
              break;
            }
          }
        }
    cells[cell(positions[i])].push_back(i);
  }
  return id;
}

TEST(FabricTile, MeshBoundaryMatchesItsTranslate) {
  for (const NamedFabric& fabric : AllFabrics()) {
    const FabricTile tile = BuildFabricTile(fabric.spec);
    const TriangleMesh& mesh = tile.mesh;
    const std::vector<size_t> id = Weld(mesh.positions);
    std::map<std::pair<size_t, size_t>, int> edge_use;
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
      for (int k = 0; k < 3; ++k) {
        const size_t a = id[mesh.indices[t + k]], b = id[mesh.indices[t + (k + 1) % 3]];
        ++edge_use[{std::min(a, b), std::max(a, b)}];
      }
    }
    std::set<size_t> boundary;
    for (const auto& [edge, uses] : edge_use) {
      if (uses == 1) boundary.insert({edge.first, edge.second});
    }
    ASSERT_FALSE(boundary.empty()) << fabric.name;
    // Every boundary vertex has a boundary vertex at its translate by one tile.
    for (const size_t v : boundary) {
      const glm::vec3 p = mesh.positions[v];
      bool matched = false;
      for (const glm::vec3 shift : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0)}) {
        for (const size_t w : boundary) {
          if (glm::distance(mesh.positions[w], p + shift) < 1e-5f) matched = true;
        }
      }
      EXPECT_TRUE(matched) << fabric.name << ": boundary vertex (" << p.x << ", " << p.y << ", " << p.z << ")";
      if (!matched) break;
    }
  }
}

TEST(FabricTile, CurvesEndWhereTheirTranslatesBegin) {
  for (const NamedFabric& fabric : AllFabrics()) {
    const FabricTile tile = BuildFabricTile(fabric.spec);
    ASSERT_FALSE(tile.curves.empty());
    for (const YarnCurve& curve : tile.curves) {
      const glm::vec3 step = curve.points.back() - curve.points.front();
      const bool one_period = glm::distance(step, glm::vec3(1, 0, 0)) < 1e-5f || glm::distance(step, glm::vec3(0, 1, 0)) < 1e-5f;
      EXPECT_TRUE(one_period) << fabric.name << ": step (" << step.x << ", " << step.y << ", " << step.z << ")";
      EXPECT_FALSE(curve.closed);
      EXPECT_GT(curve.radius, 0.0f);
    }
  }
}

TEST(FabricTile, MeshIsFiniteWithUnitNormalsAndOutwardWinding) {
  for (const NamedFabric& fabric : AllFabrics()) {
    const FabricTile tile = BuildFabricTile(fabric.spec);
    const TriangleMesh& mesh = tile.mesh;
    const size_t n = mesh.positions.size();
    ASSERT_EQ(mesh.normals.size(), n);
    ASSERT_EQ(mesh.uvs.size(), n);
    ASSERT_EQ(mesh.tangents.size(), n);
    ASSERT_EQ(tile.triangle_material.size(), mesh.triangle_count());
    for (size_t i = 0; i < n; ++i) {
      ASSERT_TRUE(Finite(mesh.positions[i]) && Finite(mesh.normals[i]) && Finite(glm::vec3(mesh.tangents[i])))
          << fabric.name;
      ASSERT_TRUE(std::isfinite(mesh.uvs[i].x) && std::isfinite(mesh.uvs[i].y)) << fabric.name;
      EXPECT_NEAR(glm::length(mesh.normals[i]), 1.0f, 1e-5f) << fabric.name;
      EXPECT_NEAR(glm::length(glm::vec3(mesh.tangents[i])), 1.0f, 1e-5f) << fabric.name;
      EXPECT_NEAR(glm::dot(mesh.normals[i], glm::vec3(mesh.tangents[i])), 0.0f, 1e-4f) << fabric.name;
      EXPECT_EQ(std::abs(mesh.tangents[i].w), 1.0f);
      EXPECT_GE(mesh.positions[i].z, tile.z_min);
      EXPECT_LE(mesh.positions[i].z, tile.z_max);
    }
    size_t outward = 0;
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
      const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      ASSERT_LT(std::max({a, b, c}), n);
      const glm::vec3 face = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
      if (glm::dot(face, mesh.normals[a] + mesh.normals[b] + mesh.normals[c]) > 0) ++outward;
      ASSERT_LT(tile.triangle_material[t / 3], tile.materials.size());
    }
    EXPECT_GT(outward, mesh.triangle_count() * 99 / 100) << fabric.name;
  }
}

TEST(FabricTile, JitterIsDeterministicPerSeed) {
  v1::FabricSpec fabric = KnitSpec(v1::KNIT_PATTERN_SEED, 0.08f);
  fabric.mutable_knit()->set_loop_jitter(kMaxLoopJitter);
  fabric.mutable_knit()->set_seed(7);
  const FabricTile a = BuildFabricTile(fabric), b = BuildFabricTile(fabric);
  ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
  EXPECT_EQ(0, std::memcmp(a.mesh.positions.data(), b.mesh.positions.data(), a.mesh.positions.size() * sizeof(glm::vec3)));
  EXPECT_EQ(0, std::memcmp(a.mesh.normals.data(), b.mesh.normals.data(), a.mesh.normals.size() * sizeof(glm::vec3)));
  EXPECT_EQ(a.mesh.indices, b.mesh.indices);
  fabric.mutable_knit()->set_seed(8);
  const FabricTile c = BuildFabricTile(fabric);
  EXPECT_NE(0, std::memcmp(a.mesh.positions.data(), c.mesh.positions.data(), a.mesh.positions.size() * sizeof(glm::vec3)));
  fabric.mutable_knit()->set_loop_jitter(0.0f);
  const FabricTile still = BuildFabricTile(fabric);
  fabric.mutable_knit()->set_seed(9);
  EXPECT_EQ(still.mesh.positions, BuildFabricTile(fabric).mesh.positions);  // no jitter: the seed is unused
}

// Fraction of a grid of vertical rays through the tile that miss every triangle of the
// tile and of its eight neighbours.
float MissFraction(const FabricTile& tile, int grid) {
  struct Triangle { glm::vec2 a, b, c, low, high; };
  std::vector<Triangle> triangles;
  const TriangleMesh& mesh = tile.mesh;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (size_t t = 0; t < mesh.indices.size(); t += 3) {
        const glm::vec2 shift(dx, dy);
        const glm::vec2 a = glm::vec2(mesh.positions[mesh.indices[t]]) + shift;
        const glm::vec2 b = glm::vec2(mesh.positions[mesh.indices[t + 1]]) + shift;
        const glm::vec2 c = glm::vec2(mesh.positions[mesh.indices[t + 2]]) + shift;
        const glm::vec2 low = glm::min(a, glm::min(b, c)), high = glm::max(a, glm::max(b, c));
        if (high.x < 0 || high.y < 0 || low.x > 1 || low.y > 1) continue;
        triangles.push_back({a, b, c, low, high});
      }
    }
  }
  auto side = [](glm::vec2 p, glm::vec2 q, glm::vec2 r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
  int misses = 0;
  for (int j = 0; j < grid; ++j) {
    for (int i = 0; i < grid; ++i) {
      const glm::vec2 ray((i + 0.5f) / grid, (j + 0.5f) / grid);
      bool hit = false;
      for (const Triangle& t : triangles) {
        if (ray.x < t.low.x || ray.y < t.low.y || ray.x > t.high.x || ray.y > t.high.y) continue;
        const float s0 = side(t.a, t.b, ray), s1 = side(t.b, t.c, ray), s2 = side(t.c, t.a, ray);
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) {
          hit = true;
          break;
        }
      }
      if (!hit) ++misses;
    }
  }
  return static_cast<float>(misses) / static_cast<float>(grid * grid);
}

TEST(FabricTile, WovenGapsAreRealHoles) {
  // Seen head-on, a single-layer plain weave lets through gap² of the light: the
  // squares between two warps and two wefts.
  const float open = MissFraction(BuildFabricTile(WovenSpec(v1::WEAVE_PATTERN_PLAIN, 0, 0, 0.3f)), 64);
  EXPECT_GT(open, 0.07f);
  EXPECT_LT(open, 0.11f);
  EXPECT_LT(MissFraction(BuildFabricTile(WovenSpec(v1::WEAVE_PATTERN_PLAIN, 0, 0, 0.0f)), 64), 0.002f);
}

TEST(FabricTile, TwistTurnsTheFibreDirectionAboutTheNormal) {
  v1::FabricSpec fabric = WovenSpec(v1::WEAVE_PATTERN_PLAIN);
  const FabricTile straight = BuildFabricTile(fabric);
  fabric.mutable_yarns(0)->set_twist_degrees(30.0f);
  const FabricTile twisted = BuildFabricTile(fabric);
  ASSERT_EQ(straight.mesh.positions, twisted.mesh.positions);
  ASSERT_EQ(straight.mesh.normals, twisted.mesh.normals);
  for (size_t i = 0; i < straight.mesh.tangents.size(); ++i) {
    const glm::vec3 t0 = straight.mesh.tangents[i], t1 = twisted.mesh.tangents[i];
    EXPECT_NEAR(glm::dot(t0, t1), std::cos(30.0f * std::numbers::pi_v<float> / 180.0f), 1e-4f);
    // Like the surface fibres of a right-handed helix about the yarn: clockwise about
    // the outward normal.
    EXPECT_LT(glm::dot(glm::cross(t0, t1), straight.mesh.normals[i]), 0.0f);
  }
}

TEST(FabricTile, MaterialsFollowTheYarns) {
  v1::FabricSpec fabric = WovenSpec(v1::WEAVE_PATTERN_PLAIN);
  v1::YarnSpec& red = *fabric.add_yarns();
  red.mutable_diffuse_albedo()->set_r(0.8f);
  red.mutable_diffuse_albedo()->set_g(0.1f);
  red.mutable_diffuse_albedo()->set_b(0.1f);
  red.set_roughness(0.2f);
  fabric.mutable_woven()->add_weft_colours(1);
  const FabricTile tile = BuildFabricTile(fabric);
  ASSERT_EQ(tile.materials.size(), 2u);
  EXPECT_EQ(tile.materials[1].diffuse_albedo, glm::vec3(0.8f, 0.1f, 0.1f));
  EXPECT_FLOAT_EQ(tile.materials[1].specular_exponent, 48.0f);
  EXPECT_FLOAT_EQ(tile.materials[0].specular_exponent, 6.0f);  // default roughness 0.5
  EXPECT_EQ(std::count(tile.triangle_material.begin(), tile.triangle_material.end(), 1u),
            static_cast<std::ptrdiff_t>(tile.triangle_material.size() / 2));  // the wefts
  EXPECT_FLOAT_EQ(SpecularExponentFromRoughness(1.0f), 1.0f);
  // A roughness the validator accepts (above 0) but float cannot square: a finite lobe.
  EXPECT_FLOAT_EQ(SpecularExponentFromRoughness(1e-30f), SpecularExponentFromRoughness(1e-4f));
  EXPECT_TRUE(std::isfinite(KajiyaKayNormalisation(SpecularExponentFromRoughness(1e-30f))));
}

// Every spec the validator accepts builds: each pattern at the extremes of its
// limits (the largest tile, the thickest yarn, the most jitter, both loop aspects,
// the widest gap and steepest inclination) gives a finite, non-empty tile.
TEST(FabricTile, SpecsAtTheValidatorsLimitsBuild) {
  std::vector<v1::FabricSpec> extremes;
  for (const float aspect : {kMinLoopAspect, kMaxLoopAspect}) {
    for (NamedFabric& knit : KnitFabrics(kMaxKnitYarnRadius)) {
      v1::KnitSpec& k = *knit.spec.mutable_knit();
      k.set_loop_aspect(aspect);
      k.set_loop_jitter(kMaxLoopJitter);
      const uint32_t wales = WithDefaults(knit.spec).knit().wales();
      const uint32_t courses = WithDefaults(knit.spec).knit().courses();
      k.set_wales(kMaxLoopsPerTileSide / wales * wales);
      k.set_courses(kMaxLoopsPerTileSide / courses * courses);
      extremes.push_back(knit.spec);
    }
  }
  for (NamedFabric& woven : WovenFabrics(0.89f)) {
    woven.spec.mutable_woven()->set_inclination_degrees(60.0f);
    woven.spec.mutable_yarns(0)->set_radius(kMaxYarnRadius);
    extremes.push_back(woven.spec);
  }
  // The largest satin repeat with its largest valid move (odd, 1 < m < n − 1).
  extremes.push_back(
      ParseSpecJson<v1::FabricSpec>(R"({"woven": {"pattern": "WEAVE_PATTERN_SATIN", "n": 32, "m": 29}})", "fabric"));
  for (const v1::FabricSpec& spec : extremes) {
    ASSERT_TRUE(Validate(spec).empty()) << FormatIssues(Validate(spec));
    const FabricTile tile = BuildFabricTile(spec);
    ASSERT_GT(tile.mesh.triangle_count(), 0u);
    for (const glm::vec3& p : tile.mesh.positions) ASSERT_TRUE(std::isfinite(p.x + p.y + p.z));
    EXPECT_LT(tile.z_min, tile.z_max);
  }
}

TEST(FabricTile, RejectsBadSpecsNamingTheField) {
  auto message_of = [](const v1::FabricSpec& fabric) {
    try {
      BuildFabricTile(fabric);
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message_of(v1::FabricSpec()).find("fabric"), std::string::npos);  // neither knit nor woven
  v1::FabricSpec gap = WovenSpec(v1::WEAVE_PATTERN_PLAIN, 0, 0, 0.95f);
  EXPECT_NE(message_of(gap).find("gap_ratio"), std::string::npos);
  // Knit loops hold thinner yarns than the general radius limit allows.
  EXPECT_NE(message_of(KnitSpec(v1::KNIT_PATTERN_STOCKINETTE, 0.15f)).find("fabric.yarns[0].radius"),
            std::string::npos);
}

// Plies and fuzz of woven yarns are not modelled: building a tile that sets them says
// so, once per yarn, on the default logger. A knit's make a yarn volume, and no warning.
TEST(FabricTile, UnmodelledPliesAndFuzzAreWarnedOfOncePerYarn) {
  std::ostringstream log;
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(
      std::make_shared<spdlog::logger>("capture", std::make_shared<spdlog::sinks::ostream_sink_st>(log)));
  const v1::FabricSpec plied = ParseSpecJson<v1::FabricSpec>(
      R"({"woven": {}, "yarns": [{"name": "four-ply test yarn", "plies": 4, "fuzz": 0.25}]})", "fabric");
  BuildFabricTile(plied);
  BuildFabricTile(plied);
  BuildFabricTile(ParseSpecJson<v1::FabricSpec>(R"({"woven": {}, "yarns": [{"name": "single-ply test yarn"}]})",
                                                "fabric"));
  const FabricTile knit = BuildFabricTile(ParseSpecJson<v1::FabricSpec>(
      R"({"knit": {}, "yarns": [{"name": "plied knit yarn", "plies": 4, "fuzz": 0.25}]})", "fabric"));
  spdlog::set_default_logger(previous);
  const std::string text = log.str();
  EXPECT_NE(text.find("yarn 'four-ply test yarn': plies (4) and fuzz (0.25) of woven yarns are not modelled yet"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("not modelled"), text.rfind("not modelled")) << "warned more than once: " << text;
  EXPECT_EQ(text.find("single-ply"), std::string::npos) << text;
  EXPECT_EQ(text.find("plied knit"), std::string::npos) << text;
  EXPECT_NE(knit.volume, nullptr);
}

// A knit of one-ply yarns without fuzz keeps its tubes: no volume, the mesh's slab.
TEST(FabricTile, OnePlyKnitWithoutFuzzHasNoVolume) {
  const FabricTile tube = BuildFabricTile(ParseSpecJson<v1::FabricSpec>(R"({"knit": {}, "yarns": [{"plies": 1}]})", "fabric"));
  EXPECT_EQ(tube.volume, nullptr);
  const FabricTile fuzzy =
      BuildFabricTile(ParseSpecJson<v1::FabricSpec>(R"({"knit": {}, "yarns": [{"plies": 1, "fuzz": 0.5}]})", "fabric"));
  ASSERT_NE(fuzzy.volume, nullptr);
  // The same centre lines, the slab widened by the flyaways' reach (half a radius).
  EXPECT_EQ(fuzzy.mesh.positions.size(), tube.mesh.positions.size());
  // One wale: tile and model units agree; the ring's vertices may fall short of the
  // tube's top by R(1 − cos(π/16)) = 0.0013.
  EXPECT_NEAR(fuzzy.z_max - tube.z_max, 0.5f * 0.07f, 2e-3f);
  EXPECT_NEAR(tube.z_min - fuzzy.z_min, 0.5f * 0.07f, 2e-3f);
}

}  // namespace
}  // namespace loom
