#include "core/scene/mesh_preparation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/scene/builtin_shapes.h"
#include "core/util/error.h"

namespace loom {
namespace {

TriangleMesh Quad() {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

TEST(MeshPreparation, ComputesNormalsAndTangentsAlongU) {
  TriangleMesh mesh = Quad();
  const auto report = PrepareMesh(mesh, "quad");
  EXPECT_EQ(report.dropped_degenerate_triangles, 0u);
  EXPECT_EQ(report.fallback_tangents, 0u);
  for (size_t v = 0; v < 4; ++v) {
    EXPECT_NEAR(glm::distance(mesh.normals[v], glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(glm::vec3(mesh.tangents[v]), glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(mesh.tangents[v].w, 1.0f);
  }
}

TEST(MeshPreparation, MirroredUvsFlipHandedness) {
  TriangleMesh mesh = Quad();
  for (glm::vec2& uv : mesh.uvs) uv.y = 1.0f - uv.y;
  PrepareMesh(mesh, "mirrored");
  for (const glm::vec4& t : mesh.tangents) EXPECT_EQ(t.w, -1.0f);
}

TEST(MeshPreparation, DropsDegenerateTrianglesAndCountsThem) {
  TriangleMesh mesh = Quad();
  mesh.positions.push_back({5, 5, 5});
  mesh.uvs.push_back({0.5f, 0.5f});
  mesh.indices.insert(mesh.indices.end(), {0, 0, 1, 4, 4, 4, 0, 1, 1});
  const auto report = PrepareMesh(mesh, "quad");
  EXPECT_EQ(report.dropped_degenerate_triangles, 3u);
  EXPECT_EQ(mesh.triangle_count(), 2u);
}

TEST(MeshPreparation, ZeroAreaUvTrianglesGetFiniteFallbackTangents) {
  TriangleMesh mesh = Quad();
  for (glm::vec2& uv : mesh.uvs) uv = {0.25f, 0.75f};  // every uv the same point
  const auto report = PrepareMesh(mesh, "squashed");
  EXPECT_EQ(report.zero_area_uv_triangles, 2u);
  EXPECT_EQ(report.fallback_tangents, 4u);
  for (size_t v = 0; v < 4; ++v) {
    const glm::vec3 t(mesh.tangents[v]);
    EXPECT_TRUE(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z));
    EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(t, mesh.normals[v]), 0.0f, 1e-5f);
  }
}

TEST(MeshPreparation, OnlyDegenerateTrianglesIsAClearError) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  try {
    PrepareMesh(mesh, "line");
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "mesh line: no triangle has a non-zero area");
  }
}

TEST(MeshPreparation, OutOfRangeIndexIsAClearError) {
  TriangleMesh mesh = Quad();
  mesh.indices.push_back(0);
  mesh.indices.push_back(1);
  mesh.indices.push_back(9);
  EXPECT_THROW(PrepareMesh(mesh, "bad"), Error);
}

TEST(MeshPreparation, BuiltinShapesHaveUnitFramesEverywhere) {
  for (TriangleMesh mesh : {MakePlane(4), MakeSphere(16), MakeCylinder(16), MakeDrape(32)}) {
    PrepareMesh(mesh, "builtin");
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    ASSERT_EQ(mesh.tangents.size(), mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      EXPECT_NEAR(glm::length(mesh.normals[v]), 1.0f, 1e-4f);
      EXPECT_NEAR(glm::length(glm::vec3(mesh.tangents[v])), 1.0f, 1e-4f);
      EXPECT_NEAR(glm::dot(mesh.normals[v], glm::vec3(mesh.tangents[v])), 0.0f, 1e-4f);
    }
  }
}

TEST(MeshPreparation, BuiltinShapesHaveNoDegenerateTriangles) {
  // The sphere's pole rows are fans of one triangle a quad (it used to emit two,
  // one of them with two vertices on the pole, and PrepareMesh warned on every build).
  for (int segments : {1, 2, 32}) {
    TriangleMesh sphere = MakeSphere(segments);
    const size_t triangles = sphere.indices.size() / 3;
    const MeshPreparationReport report = PrepareMesh(sphere, "sphere");
    EXPECT_EQ(report.dropped_degenerate_triangles, 0u) << segments;
    EXPECT_EQ(report.zero_area_uv_triangles, 0u) << segments;
    const size_t rings = std::max(segments, 2), around = 2 * rings;
    EXPECT_EQ(triangles, 2 * around * (rings - 1)) << segments;  // two a quad, one at each pole
  }
  for (TriangleMesh mesh : {MakePlane(4), MakeCylinder(16), MakeDrape(32)}) {
    EXPECT_EQ(PrepareMesh(mesh, "builtin").dropped_degenerate_triangles, 0u);
  }
}

TEST(MeshPreparation, DrapeFollowsTheSphereAndHangsBelowIt) {
  TriangleMesh drape = MakeDrape(64);
  PrepareMesh(drape, "drape");
  float top = -INFINITY, bottom = INFINITY;
  for (const glm::vec3& p : drape.positions) {
    top = std::max(top, p.z);
    bottom = std::min(bottom, p.z);
    // Never inside the sphere it rests on.
    EXPECT_GE(glm::length(p), 0.5f - 1e-4f);
  }
  EXPECT_NEAR(top, 0.5f, 1e-3f);  // the centre of the cloth sits on the sphere's top
  EXPECT_LT(bottom, -0.5f);       // the corners hang well below the equator
  // The centre's normal points up.
  const size_t centre = drape.positions.size() / 2;
  EXPECT_GT(drape.normals[centre].z, 0.99f);
}

}  // namespace
}  // namespace loom
