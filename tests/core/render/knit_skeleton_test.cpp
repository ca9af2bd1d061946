// The knit skeleton on an animated cloth: a frame of a knit animation, as a scene
// mesh, carries the fabric's yarns on that frame's surface (the lumislice renderer
// draws what PlaceKnitSkeleton places, so a frame range rendered with it shows the
// knit moving with the cloth).

#include "core/render/knit_skeleton.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/animate/animation.h"
#include "core/animate/closest_point.h"
#include "core/animate/cloth_sequence_io.h"
#include "core/scene/gltf_loader.h"
#include "core/scene/mesh_preparation.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"

namespace loom {
namespace {

// The farthest skeleton point from the mesh's surface.
float FarthestFromSurface(const KnitSkeleton& skeleton, const TriangleMesh& mesh) {
  float farthest = 0.0f;
  for (const SkeletonChain& chain : skeleton.chains) {
    for (const glm::vec3& p : chain.points) {
      float nearest = std::numeric_limits<float>::infinity();
      for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const glm::vec3 a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]],
                        c = mesh.positions[mesh.indices[i + 2]];
        nearest = std::min(nearest, glm::distance(p, animate::ClosestPointOnTriangle(p, a, b, c).point));
      }
      farthest = std::max(farthest, nearest);
    }
  }
  return farthest;
}

TEST(KnitSkeletonTest, AKnitAnimationsFrameCarriesTheYarnsOnItsSurface) {
  // 7 loops by 9 courses hung by the top course and swung: a 2 × 2 stockinette tile
  // repeated (7 − 1) / 2 × (9 − 1) / 2 times puts a tile loop on each mass point.
  const MeshSequence sequence = animate::ClothSequence(animate::RunAnimation(ParseSpecJson<v1::AnimationSpec>(
      R"({"cloth": {"loops": 7, "courses": 9, "wale_axis": {"z": -1}}, "pins": [{"course": 0}],
          "initial_velocity": {"y": 2}, "duration_seconds": 0.4})",
      "animation")));
  const v1::FabricSpec fabric =
      WithDefaults(ParseSpecJson<v1::FabricSpec>(R"({"knit": {"wales": 2, "courses": 2}})", "fabric"));
  const auto frame = [&](size_t k) {
    TriangleMesh mesh = SequenceFrame(sequence, k, "sequence");
    PrepareMesh(mesh, "sequence");
    return mesh;
  };
  const TriangleMesh first = frame(0), last = frame(10);
  const KnitSkeleton still = PlaceKnitSkeleton(fabric, first, {3, 4});
  const KnitSkeleton swung = PlaceKnitSkeleton(fabric, last, {3, 4});
  ASSERT_GT(swung.segment_count(), 100u);
  EXPECT_EQ(swung.segment_count(), still.segment_count());
  // Within a yarn's height of its own frame's surface (loops are 1 apart; the
  // skeleton rises 0.27 above it), not of the other frame's.
  EXPECT_LT(FarthestFromSurface(still, first), 0.35f);
  EXPECT_LT(FarthestFromSurface(swung, last), 0.35f);
  EXPECT_GT(FarthestFromSurface(swung, first), 0.8f);
}

}  // namespace
}  // namespace loom
