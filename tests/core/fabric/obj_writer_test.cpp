#include "core/scene/obj_writer.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "core/fabric/fabric_tile.h"
#include "core/util/file_io.h"
#include "fabric_specs.h"

namespace loom {
namespace {

TEST(ObjWriter, RepeatsTheTileAndIndexesFromOne) {
  const FabricTile tile = BuildFabricTile(WovenSpec(v1::WEAVE_PATTERN_PLAIN));
  const auto path = std::filesystem::path(::testing::TempDir()) / "loom_obj_writer_test" / "tile.obj";
  WriteObj(tile.mesh, path, 2, 3);
  std::istringstream in(ReadFile(path));
  size_t v = 0, vt = 0, vn = 0, f = 0;
  float max_x = -1, max_y = -1;
  uint64_t max_index = 0;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    if (tag == "v") {
      ++v;
      float x, y, z;
      fields >> x >> y >> z;
      max_x = std::max(max_x, x);
      max_y = std::max(max_y, y);
    } else if (tag == "vt") {
      ++vt;
    } else if (tag == "vn") {
      ++vn;
    } else if (tag == "f") {
      ++f;
      std::string corner;
      while (fields >> corner) {
        uint64_t index = std::stoull(corner.substr(0, corner.find('/')));
        ASSERT_GE(index, 1u);
        max_index = std::max(max_index, index);
        ASSERT_EQ(std::count(corner.begin(), corner.end(), '/'), 2);
      }
    }
  }
  const size_t vertices = tile.mesh.positions.size();
  EXPECT_EQ(v, 6 * vertices);
  EXPECT_EQ(vt, vertices);
  EXPECT_EQ(vn, vertices);
  EXPECT_EQ(f, 6 * tile.mesh.triangle_count());
  EXPECT_EQ(max_index, 6 * vertices);
  EXPECT_GT(max_x, 1.5f);  // the copies sit side by side
  EXPECT_GT(max_y, 2.5f);
}

}  // namespace
}  // namespace loom
