#include "core/methods/fabric_method.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/util/error.h"

namespace loom {
namespace {

TEST(FabricMethods, AreFoundByNameAndIdAndUnknownOnesAreRefused) {
  for (const char* name : {"svbrdf", "tabulated", "factored", "neural"}) {
    const FabricMethod* method = MethodNamed(name);
    ASSERT_NE(method, nullptr) << name;
    EXPECT_EQ(&MethodOf(method->id()), method) << name;
    EXPECT_NE(MethodNames().find(name), std::string::npos) << name;
  }
  EXPECT_EQ(&MethodOf(v1::FABRIC_METHOD_UNSPECIFIED), MethodNamed("svbrdf"));
  EXPECT_EQ(MethodNamed("lafortune"), nullptr);
  EXPECT_THROW(MethodOf(static_cast<v1::FabricMethod>(99)), Error);
}

// A view grid and its heights that disagree are refused before any GL texture is
// made (no context here: reaching GL would crash, not throw).
TEST(FabricSurface, RefusesViewHeightsThatDoNotFillTheViewGrid) {
  for (const auto& [view_side, heights] : {std::pair{3, 8}, std::pair{3, 10}, std::pair{0, 0}, std::pair{-2, 4}}) {
    try {
      FabricSurface(1, 8, view_side, 0, std::vector<float>(static_cast<size_t>(heights), 0.0f));
      FAIL() << view_side << " " << heights;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      EXPECT_NE(std::string(e.what()).find("view heights for a " + std::to_string(view_side)), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace loom
