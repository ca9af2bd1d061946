#include "core/scene/obj_loader.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace loom {
namespace {

constexpr const char* kQuad = R"(# a unit quad as two triangles
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
f 1/1/1 2/2/1 3/3/1 4/4/1
)";

std::string ErrorOf(const std::string& text) {
  try {
    ParseObj(text, "test.obj");
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    return error.what();
  }
  return "";
}

TEST(ObjLoader, TriangulatesAndSharesVertices) {
  const TriangleMesh mesh = ParseObj(kQuad, "quad.obj");
  EXPECT_EQ(mesh.triangle_count(), 2u);
  EXPECT_EQ(mesh.positions.size(), 4u);
  ASSERT_EQ(mesh.uvs.size(), 4u);
  ASSERT_EQ(mesh.normals.size(), 4u);
  for (size_t v = 0; v < 4; ++v) {
    EXPECT_EQ(mesh.uvs[v], glm::vec2(mesh.positions[v]));  // this quad's uv equals its xy
    EXPECT_EQ(mesh.normals[v], glm::vec3(0, 0, 1));
  }
}

TEST(ObjLoader, SplitsVerticesWithDifferentUvs) {
  // A seam: position 1 has two uvs.
  const TriangleMesh mesh = ParseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                                     "f 1/1 2/2 3/3\nf 1/4 3/3 2/2\n",
                                     "seam.obj");
  EXPECT_EQ(mesh.positions.size(), 4u);
  EXPECT_TRUE(mesh.normals.empty());  // none in the file: PrepareMesh computes them
}

TEST(ObjLoader, MissingUvsIsAClearError) {
  EXPECT_EQ(ErrorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            "mesh test.obj: has no texture coordinates (vt): a fabric is tiled over the mesh through its UVs");
}

TEST(ObjLoader, NonFiniteNumbersAreAClearError) {
  for (const char* bad : {"nan", "-inf", "1e999", "NaN"}) {
    EXPECT_EQ(ErrorOf(std::string("v 0 0 0\nv ") + bad + " 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"),
              "mesh test.obj: contains a non-finite number (NaN or Inf)")
        << bad;
  }
}

TEST(ObjLoader, NoFacesIsAClearError) {
  EXPECT_EQ(ErrorOf("v 0 0 0\nvt 0 0\n"), "mesh test.obj: has no faces");
}

TEST(ObjLoader, FaceVertexWithoutUvIsAClearError) {
  EXPECT_NE(ErrorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3\n").find("without a texture coordinate"),
            std::string::npos);
}

}  // namespace
}  // namespace loom
