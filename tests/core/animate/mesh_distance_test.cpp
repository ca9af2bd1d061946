#include "core/animate/mesh_distance.h"

#include <gtest/gtest.h>

#include <random>

#include "core/animate/collider.h"
#include "core/animate/knit_simulation.h"
#include "core/scene/builtin_shapes.h"
#include "core/util/error.h"

namespace loom::animate {
namespace {

// An axis-aligned box of half extents h about c, its 12 triangles facing out,
// each face's corners its own (as an OBJ with per-face uvs has them).
TriangleMesh BoxMesh(glm::vec3 c, glm::vec3 h) {
  TriangleMesh mesh;
  for (int axis = 0; axis < 3; ++axis) {
    for (const float side : {-1.0f, 1.0f}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto base = static_cast<uint32_t>(mesh.positions.size());
      for (const glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
        glm::vec3 p(0.0f);
        p[axis] = side;
        p[u] = corner.x;
        p[v] = corner.y;
        mesh.positions.push_back(c + p * h);
      }
      // (u, v, axis) is right-handed: counter-clockwise about +axis on the + side.
      if (side > 0) {
        mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
      } else {
        mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
      }
    }
  }
  return mesh;
}

TEST(MeshDistance, ABoxMeshGivesTheBoxsSignedDistanceAndNormalEverywhere) {
  const glm::vec3 centre(1, 2, 3), half(2, 1, 0.5f);
  const MeshDistance mesh(BoxMesh(centre, half), "box");
  const Collider box = Collider::Box(centre, half);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-4.0f, 4.0f);
  int inside = 0;
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 p = centre + glm::vec3(coordinate(random), coordinate(random), coordinate(random)) * 0.8f;
    const Contact expected = box.Nearest(p, glm::vec3(0.0f)), got = mesh.Nearest(p);
    ASSERT_NEAR(got.distance, expected.distance, 1e-4f) << p.x << " " << p.y << " " << p.z;
    // Inside, the box's normal is its nearest face's; outside, along the offset.
    if (std::abs(expected.distance) > 1e-3f) {
      EXPECT_NEAR(glm::distance(got.normal, expected.normal), 0.0f, 1e-3f) << p.x << " " << p.y << " " << p.z;
    }
    inside += got.distance < 0.0f;
  }
  EXPECT_GT(inside, 20);  // some points were inside
  // Nearest a corner and an edge from outside: the corner's and the edge's
  // pseudo-normals give the sign.
  EXPECT_NEAR(mesh.Nearest(centre + half + glm::vec3(0.1f)).distance, std::sqrt(0.03f), 1e-5f);
  EXPECT_NEAR(mesh.Nearest(centre + glm::vec3(half.x + 0.3f, half.y + 0.4f, 0)).distance, 0.5f, 1e-5f);
}

TEST(MeshDistance, TheSignIsRightNearASharpCorner) {
  // A square pyramid, its apex 3 above a 2 × 2 base: around the apex the nearest
  // feature is often the apex itself, where the faces' own normals disagree on
  // the side (the pseudo-normal does not).
  TriangleMesh pyramid;
  pyramid.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 3}};
  pyramid.indices = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 2, 1, 0, 3, 2};
  const MeshDistance mesh(pyramid, "pyramid");
  const auto inside = [&](glm::vec3 p) {
    for (size_t t = 0; t < 6; ++t) {
      const glm::vec3 a = pyramid.positions[pyramid.indices[3 * t]], b = pyramid.positions[pyramid.indices[3 * t + 1]],
                      c = pyramid.positions[pyramid.indices[3 * t + 2]];
      if (glm::dot(p - a, glm::cross(b - a, c - a)) > 0.0f) return false;
    }
    return true;
  };
  std::mt19937 random(3);
  std::uniform_real_distribution<float> offset(-0.5f, 0.5f);
  int wrong = 0, in = 0;
  for (int k = 0; k < 4000; ++k) {
    const glm::vec3 p = glm::vec3(0, 0, 2.8f) + glm::vec3(offset(random), offset(random), offset(random));
    const bool is_inside = inside(p);
    in += is_inside;
    wrong += (mesh.Nearest(p).distance < 0.0f) != is_inside;
  }
  EXPECT_GT(in, 20);
  EXPECT_EQ(wrong, 0);
}

TEST(MeshDistance, ASphereMeshWeldsItsSeamAndTellsInsideFromOutside) {
  TriangleMesh sphere = MakeSphere(32);
  for (glm::vec3& p : sphere.positions) p *= 5.0f;
  const MeshDistance mesh(sphere, "sphere");
  // Within the tessellation's error (5 (1 − cos(π/32)) ≈ 0.024) of the sphere's.
  for (const glm::vec3 p : {glm::vec3(0, 0, 7), glm::vec3(0, 0, -3), glm::vec3(3, 4, 1), glm::vec3(0.1f, 0, 0),
                            glm::vec3(-6, 2, -2)}) {
    EXPECT_NEAR(mesh.Nearest(p).distance, glm::length(p) - 5.0f, 0.03f) << p.x << " " << p.y << " " << p.z;
  }
}

TEST(MeshDistance, RefusesAnOpenMeshNamingIt) {
  TriangleMesh box = BoxMesh(glm::vec3(0), glm::vec3(1));
  box.indices.resize(box.indices.size() - 3);  // one triangle short
  try {
    MeshDistance mesh(box, "objects/chair.obj");
    FAIL() << "an open mesh was taken";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find("mesh collider objects/chair.obj: not closed"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(MeshDistance(TriangleMesh{}, "empty"), Error);
  // One face turned round: its neighbours disagree with it.
  box = BoxMesh(glm::vec3(0), glm::vec3(1));
  std::swap(box.indices[1], box.indices[2]);
  try {
    MeshDistance mesh(box, "box");
    FAIL() << "a mesh wound both ways was taken";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("its faces are not wound alike"), std::string::npos) << error.what();
  }
}

TEST(MeshDistance, AMeshWoundInwardsIsTurnedRound) {
  TriangleMesh box = BoxMesh(glm::vec3(0), glm::vec3(1));
  for (size_t t = 0; t < box.triangle_count(); ++t) std::swap(box.indices[3 * t + 1], box.indices[3 * t + 2]);
  const MeshDistance mesh(box, "box");
  EXPECT_NEAR(mesh.Nearest(glm::vec3(0, 0, 3)).distance, 2.0f, 1e-5f);
  EXPECT_NEAR(mesh.Nearest(glm::vec3(0, 0, 0.5f)).distance, -0.5f, 1e-5f);
  EXPECT_NEAR(mesh.Nearest(glm::vec3(0, 0, 3)).normal.z, 1.0f, 1e-5f);
}

// A 4 × 4 patch dropped onto a box from 3 loops above its top: where it rests.
std::vector<glm::vec3> DropOnto(const Collider& box) {
  const KnitCloth cloth = FlatKnitCloth(4, 4, 1.0f, 1.0f, glm::vec3(-1.5f, -1.5f, 4), glm::vec3(1, 0, 0),
                                        glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, KnitMechanics{}, {box});
  sim.Advance(2.0f, 0.04f);
  EXPECT_GE(sim.min_collider_distance(), 0.0f);
  EXPECT_EQ(sim.counts().penetrations, 0);
  return sim.positions();
}

TEST(MeshDistance, AClothRestsOnABoxMeshAsOnTheBox) {
  const glm::vec3 centre(0, 0, 0), half(3, 3, 1);
  const std::vector<glm::vec3> on_mesh =
      DropOnto(Collider::Mesh(std::make_shared<const MeshDistance>(BoxMesh(centre, half), "box")));
  const std::vector<glm::vec3> on_box = DropOnto(Collider::Box(centre, half));
  for (size_t p = 0; p < on_box.size(); ++p) {
    EXPECT_NEAR(glm::distance(on_mesh[p], on_box[p]), 0.0f, 1e-3f) << p;
  }
  // In the top's fibre layer (T = 0.9 above it).
  EXPECT_GT(on_box[5].z, 1.3f);
  EXPECT_LT(on_box[5].z, 1.9f);
}

}  // namespace
}  // namespace loom::animate
