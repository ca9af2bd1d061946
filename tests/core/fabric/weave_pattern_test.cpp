#include "core/fabric/weave_pattern.h"

#include <gtest/gtest.h>

#include <string>

#include "core/spec/defaults.h"

namespace loom {
namespace {

WeaveMatrix Weave(v1::WeavePattern pattern, uint32_t n = 0, uint32_t m = 0) {
  v1::FabricSpec fabric;
  fabric.mutable_woven()->set_pattern(pattern);
  fabric.mutable_woven()->set_n(n);
  fabric.mutable_woven()->set_m(m);
  return WeaveMatrix(WithDefaults(fabric).woven());
}

// Rows are wefts, 'X' where the warp is on top.
std::string Picture(const WeaveMatrix& weave) {
  std::string picture;
  for (uint32_t weft = 0; weft < weave.size(); ++weft) {
    for (uint32_t warp = 0; warp < weave.size(); ++warp) picture += weave.WarpOver(warp, weft) ? 'X' : '.';
    picture += '\n';
  }
  return picture;
}

TEST(WeavePattern, Plain) { EXPECT_EQ(Picture(Weave(v1::WEAVE_PATTERN_PLAIN)), "X.\n.X\n"); }

TEST(WeavePattern, TwillFloatsNOverMUnderShiftedByOne) {
  EXPECT_EQ(Picture(Weave(v1::WEAVE_PATTERN_TWILL, 3, 1)), "XXX.\nXX.X\nX.XX\n.XXX\n");
}

TEST(WeavePattern, SatinHasOneInterlacingPerThreadAndMovesByM) {
  const WeaveMatrix satin = Weave(v1::WEAVE_PATTERN_SATIN, 5);  // default move 2
  ASSERT_EQ(satin.size(), 5u);
  EXPECT_EQ(Picture(satin), ".XXXX\nXX.XX\nXXXX.\nX.XXX\nXXX.X\n");
}

TEST(WeavePattern, BasketIsPlainWithGroupedYarns) {
  EXPECT_EQ(Picture(Weave(v1::WEAVE_PATTERN_BASKET, 2)), "XX..\nXX..\n..XX\n..XX\n");
}

TEST(WeavePattern, IndicesWrapAroundTheRepeat) {
  const WeaveMatrix twill = Weave(v1::WEAVE_PATTERN_TWILL, 2, 1);
  EXPECT_EQ(twill.WarpOver(4, 7), twill.WarpOver(1, 1));
}

}  // namespace
}  // namespace loom
