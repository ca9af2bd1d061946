// The pieces of `loom render --frames`: the range, the output pattern, the
// sequence objects; each bad value refused naming its flag.

#include "client/frame_range.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/util/error.h"

namespace loom::client {
namespace {

using ::testing::HasSubstr;

std::string ErrorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& error) {
    return error.what();
  }
  return "no error";
}

TEST(FrameRangeTest, RangesParseInclusiveAndBadOnesNameTheFlagAndTheLimit) {
  const FrameRange range = ParseFrameRange("3..10");
  EXPECT_EQ(range.first, 3u);
  EXPECT_EQ(range.last, 10u);
  EXPECT_EQ(range.size(), 8u);
  EXPECT_EQ(ParseFrameRange("7").size(), 1u);
  EXPECT_EQ(ParseFrameRange("0..3000").size(), 3001u);
  EXPECT_THAT(ErrorOf([] { ParseFrameRange("10..3"); }), HasSubstr("--frames: 10..3 ends before it begins"));
  EXPECT_THAT(ErrorOf([] { ParseFrameRange("0..3001"); }), HasSubstr("--frames: frame 3001 is past"));
  EXPECT_THAT(ErrorOf([] { ParseFrameRange("0..3001"); }), HasSubstr("(3000)"));
  for (const char* bad : {"", "..", "a..b", "1..", "..4", "-1..2", "1...4", "1..2..3", "1-4"}) {
    EXPECT_THAT(ErrorOf([bad] { ParseFrameRange(bad); }), HasSubstr("is not A..B or A")) << bad;
  }
}

TEST(FrameRangeTest, PatternsTakeOneFfmpegConversion) {
  EXPECT_EQ(FramePath("out/f_%04d.png", 7), "out/f_0007.png");
  EXPECT_EQ(FramePath("out/f_%04d.png", 12345), "out/f_12345.png");
  EXPECT_EQ(FramePath("%d.exr", 42), "42.exr");
  EXPECT_EQ(FramePath("100%%/f%02d.png", 3), "100%/f03.png");
  EXPECT_THAT(ErrorOf([] { CheckFramePattern("frame.png"); }), HasSubstr("--out: frame.png has no frame number"));
  EXPECT_THAT(ErrorOf([] { CheckFramePattern("100%%.png"); }), HasSubstr("has no frame number"));
  for (const char* bad : {"f%d_%d.png", "f%5d.png", "f%s.png", "f%00d.png", "f%010d.png", "f%.png", "f%"}) {
    EXPECT_THAT(ErrorOf([bad] { CheckFramePattern(bad); }), HasSubstr("needs exactly one frame number conversion"))
        << bad;
  }
}

TEST(FrameRangeTest, SequenceObjectsAreTheGltfMeshesAndAtLeastOne) {
  v1::SceneSpec scene;
  scene.add_objects()->mutable_mesh()->set_obj_path("a.obj");
  scene.add_objects()->mutable_mesh()->set_gltf_path("scarf.glb");
  scene.add_objects()->mutable_mesh()->set_builtin(v1::BUILTIN_SHAPE_PLANE);
  scene.add_objects()->mutable_mesh()->set_gltf_path("ball.glb");
  EXPECT_EQ(SequenceObjects(scene), (std::vector<int>{1, 3}));
  scene.mutable_objects()->DeleteSubrange(1, 1);
  scene.mutable_objects()->DeleteSubrange(2, 1);
  EXPECT_THAT(ErrorOf([&] { SequenceObjects(scene); }), HasSubstr("--frames: the scene has no glTF mesh"));
}

}  // namespace
}  // namespace loom::client
