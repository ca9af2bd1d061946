#include "core/scene/obj_loader.h"

#include <gtest/gtest.h>

#include "core/spec/limits.h"
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

constexpr const char* kTriangleHead = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";

std::string ErrorOf(const std::string& text, MeshLimits limits = {}) {
  try {
    ParseObj(text, "test.obj", limits);
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

TEST(ObjLoader, SplitsAQuadAlongItsShorterDiagonal) {
  // The diagonal 1-3 (0-based) is shorter than 0-2: triangles (0,1,3) and (1,2,3).
  const TriangleMesh mesh = ParseObj("v 0 0 0\nv 1 0 0\nv 3 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1 4/1\n", "kite.obj");
  ASSERT_EQ(mesh.indices.size(), 6u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
}

TEST(ObjLoader, FansPolygons) {
  const TriangleMesh mesh = ParseObj(
      "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 2 0\nv -1 1 0\nvt 0 0\nf 1/1 2/1 3/1 4/1 5/1 6/1\n", "hexagon.obj");
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5}));
}

TEST(ObjLoader, SplitsVerticesWithDifferentUvs) {
  // A seam: position 1 has two uvs.
  const TriangleMesh mesh = ParseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                                     "f 1/1 2/2 3/3\nf 1/4 3/3 2/2\n",
                                     "seam.obj");
  EXPECT_EQ(mesh.positions.size(), 4u);
  EXPECT_TRUE(mesh.normals.empty());  // none in the file: PrepareMesh computes them
}

TEST(ObjLoader, NegativeIndicesCountBackFromTheLastDefined) {
  const TriangleMesh relative = ParseObj(std::string(kTriangleHead) + "f -3/-3 -2/-2 -1/-1\n", "relative.obj");
  const TriangleMesh absolute = ParseObj(std::string(kTriangleHead) + "f 1/1 2/2 3/3\n", "absolute.obj");
  EXPECT_EQ(relative.positions, absolute.positions);
  EXPECT_EQ(relative.uvs, absolute.uvs);
  EXPECT_EQ(relative.indices, absolute.indices);
}

TEST(ObjLoader, ReadsPiecesOfAnySize) {
  const TriangleMesh whole = ParseObj(kQuad, "quad.obj");
  const std::string text = kQuad;
  for (size_t piece : {size_t{1}, size_t{3}, size_t{17}}) {
    ObjParser parser("quad.obj");
    for (size_t offset = 0; offset < text.size(); offset += piece) parser.Feed(std::string_view(text).substr(offset, piece));
    const TriangleMesh mesh = parser.Finish();
    EXPECT_EQ(mesh.positions, whole.positions) << piece;
    EXPECT_EQ(mesh.indices, whole.indices) << piece;
  }
}

TEST(ObjLoader, AcceptsCommonVariants) {
  // CRLF, a trailing comment, vertex colours, a w coordinate, a 1-number vt, '+'
  // signs, and statements Loom does not use; no final newline.
  const TriangleMesh mesh = ParseObj(
      "mtllib a.mtl\r\no cloth\r\nv 0 0 0 1 0 0\r\nv +1 0 0 1.0\r\nv 0 1 0 # top\r\nvt 0.5\r\ng g1\r\ns off\r\n"
      "usemtl m\r\nl 1 2\r\nf 1/1 2/1 3/1",
      "variants.obj");
  EXPECT_EQ(mesh.triangle_count(), 1u);
  EXPECT_EQ(mesh.positions[1], glm::vec3(1, 0, 0));
  EXPECT_EQ(mesh.uvs[0], glm::vec2(0.5f, 0.0f));
}

TEST(ObjLoader, AMeshWithoutUvsHasNone) {
  // Plain diffuse objects need none: the scene decides (core/scene/scene_geometry.h).
  const TriangleMesh mesh = ParseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "plain.obj");
  EXPECT_EQ(mesh.triangle_count(), 1u);
  EXPECT_TRUE(mesh.uvs.empty());
}

// The crash a client written from the protos found (issue 22): faces that refer
// past the end of the vertex list, or before its start, killed loom-server.
TEST(ObjLoader, IndicesOutOfRangeAreClearErrors) {
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2 100000000/3\n"),
            "mesh test.obj: line 7: face refers to position 100000000, but 3 positions are defined before it");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2 -4/3\n"),
            "mesh test.obj: line 7: face refers to position -4, but 3 positions are defined before it");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2 3/7\n"),
            "mesh test.obj: line 7: face refers to texture coordinate 7, but 3 texture coordinates are defined "
            "before it");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "vn 0 0 1\nf 1/1/1 2/2/1 3/3/2\n"),
            "mesh test.obj: line 8: face refers to normal 2, but 1 normal is defined before it");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 0/1 2/2 3/3\n"),
            "mesh test.obj: line 7: face position index 0 (OBJ counts from 1)");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2 99999999999999999999999/3\n"),
            "mesh test.obj: line 7: face index '99999999999999999999999' is not an integer");
  // A face before the vertices it names: OBJ refers to what is defined above.
  EXPECT_EQ(ErrorOf("f 1/1 2/2 3/3\n" + std::string(kTriangleHead)),
            "mesh test.obj: line 1: face refers to position 1, but 0 positions are defined before it");
}

TEST(ObjLoader, MalformedStatementsAreClearErrors) {
  EXPECT_EQ(ErrorOf("v 0 0\n"), "mesh test.obj: line 1: v needs at least 3 numbers");
  EXPECT_EQ(ErrorOf("v 0 0 x\n"), "mesh test.obj: line 1: 'x' in v is not a number");
  EXPECT_EQ(ErrorOf("vn 0 0 1 0\n"), "mesh test.obj: line 1: vn has more than 3 numbers");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2\n"),
            "mesh test.obj: line 7: a face needs at least 3 corners, this one has 2");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2 3/3/\n"),
            "mesh test.obj: line 7: face corner '3/3/' is not v, v/vt, v//vn or v/vt/vn");
  EXPECT_EQ(ErrorOf("v 0 0 0\n" + std::string(kMaxObjLineBytes + 1, ' ') + "\n"),
            "mesh test.obj: line 2: longer than " + std::to_string(kMaxObjLineBytes) + " bytes");
}

TEST(ObjLoader, NonFiniteNumbersAreAClearError) {
  for (const char* bad : {"nan", "-inf", "1e999", "NaN"}) {
    EXPECT_EQ(ErrorOf(std::string("v 0 0 0\nv ") + bad + " 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"),
              std::string("mesh test.obj: line 2: '") + bad + "' in v is not a finite number (NaN or Inf)")
        << bad;
  }
}

TEST(ObjLoader, NoFacesIsAClearError) {
  EXPECT_EQ(ErrorOf("v 0 0 0\nvt 0 0\n"), "mesh test.obj: has no faces");
}

TEST(ObjLoader, MixedCornersAreClearErrors) {
  EXPECT_NE(ErrorOf(std::string(kTriangleHead) + "f 1/1 2 3\n").find("without a texture coordinate"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kTriangleHead) + "vn 0 0 1\nf 1/1/1 2/2/1 3/3\n").find("without a normal"),
            std::string::npos);
  EXPECT_NE(ErrorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nvt 0 0\nf 1/1 2/1 3/1\n").find("earlier ones have none"),
            std::string::npos);
}

// The caps end the parse at the line that passes them, not after the whole file.
TEST(ObjLoader, CapsStopTheParseWhereTheyArePassed) {
  MeshLimits limits;
  limits.triangles = 2;
  const std::string three = std::string(kTriangleHead) + "f 1/1 2/2 3/3\nf 1/1 2/2 3/3\nf 1/1 2/2 3/3\nf 1/1 2/2 3/3\n";
  EXPECT_EQ(ErrorOf(three, limits), "mesh test.obj: line 9: more than 2 triangles");
  // A polygon is fanned as it is read: one long face line is capped too.
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2 3/3 1/1 2/2 3/3\n", limits),
            "mesh test.obj: line 7: more than 2 triangles");

  limits = MeshLimits();
  limits.vertices = 2;
  EXPECT_EQ(ErrorOf(kTriangleHead, limits), "mesh test.obj: line 3: more than 2 positions (v)");
  limits.vertices = 3;
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "vt 1 1\n", limits),
            "mesh test.obj: line 7: more than 3 texture coordinates (vt)");
  EXPECT_EQ(ErrorOf(std::string(kTriangleHead) + "f 1/1 2/2 3/3\nf 1/2 2/3 3/1\n", limits),
            "mesh test.obj: line 8: more than 3 distinct vertices");
}

}  // namespace
}  // namespace loom
