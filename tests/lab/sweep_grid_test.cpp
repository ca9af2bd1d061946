#include "lab/sweep_grid.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::lab {
namespace {

const std::string kSceneSet =
    std::string(LOOM_SOURCE_DIR) + "/bench/scenes/quick_set.json";

// Writes a grid file over the quick scene set with `configurations` and `extra`
// top-level fields; returns the error message LoadSweepGrid gives, or "" if it
// loads.
std::string GridError(const std::string &configurations,
                      const std::string &extra = "") {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("loom_grid_" + std::to_string(::getpid()) + ".json");
  WriteFileAtomic(path, "{\"scene_set\": \"" + kSceneSet + "\", " + extra +
                            "\"configurations\": [" + configurations + "]}");
  std::string message;
  try {
    LoadSweepGrid(path);
  } catch (const Error &e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument) << e.what();
    message = e.what();
  } catch (const std::exception &e) {
    ADD_FAILURE() << "not a loom::Error: " << e.what();
    message = e.what();
  }
  std::filesystem::remove(path);
  return message;
}

TEST(SweepGrid, MergesEachConfigurationOntoTheBase) {
  const std::filesystem::path grid_file =
      std::filesystem::path(LOOM_SOURCE_DIR) / "bench/sweep_quick.json";
  const SweepGrid grid = LoadSweepGrid(grid_file);
  EXPECT_EQ(grid.name, "sweep_quick");
  ASSERT_EQ(grid.scenes.size(), 2u);
  ASSERT_EQ(grid.configurations.size(), 5u);
  const SweepConfiguration &res8 = grid.configurations[1];
  EXPECT_EQ(res8.name, "tiny-res8");
  EXPECT_EQ(res8.precompute.spatial_resolution(), 8u); // its own
  EXPECT_EQ(res8.precompute.view_directions(), 9u);    // the base's
  EXPECT_EQ(res8.precompute.indirect_bounces(),
            0u); // an explicit zero of the base survives
  const v1::SceneSpec scene = ConfiguredScene(res8, grid.scenes[0]);
  EXPECT_EQ(scene.objects(0).fabric().precompute().spatial_resolution(), 8u);
  EXPECT_EQ(scene.render().width(), 64u); // the scene's frame, not the grid's
  EXPECT_EQ(grid.configurations[3].method, v1::RENDER_METHOD_REFERENCE);
}

TEST(SweepGrid, BadGridsAreRejectedNamingTheField) {
  EXPECT_THAT(GridError("{\"name\": \"a\", \"precompute\": {\"lobes\": 4}}"),
              testing::HasSubstr("configurations[a]"));
  EXPECT_THAT(GridError("{\"name\": \"a\", \"precompute\": {\"lobes\": 4}}"),
              testing::HasSubstr("lobes: 4 exceeds 3"));
  EXPECT_THAT(
      GridError("{\"name\": \"a\", \"method\": \"tiled\"}"),
      testing::HasSubstr(
          "is not reference, lumislice, svbrdf, tabulated, factored, neural"));
  EXPECT_THAT(GridError("{\"name\": \"a\"}, {\"name\": \"a\"}"),
              testing::HasSubstr("used twice"));
  EXPECT_THAT(GridError("{\"name\": \"a\", \"colour\": 1}"),
              testing::HasSubstr("configurations[a].colour: unknown field"));
  EXPECT_THAT(GridError("{\"name\": \"a\", \"scenes\": [\"nothing.*\"]}"),
              testing::HasSubstr("no scene of the grid matches"));
  EXPECT_THAT(GridError("{\"name\": \"a\"}", "\"flicker_frames\": 0, "),
              testing::HasSubstr("flicker_frames"));
  EXPECT_THAT(GridError("{\"name\": \"a\"}", "\"sceens\": [], "),
              testing::HasSubstr("sceens: unknown field"));
  EXPECT_EQ(GridError("{\"name\": \"a\"}"), "");
}

} // namespace
} // namespace loom::lab
