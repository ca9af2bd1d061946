#include "server/parse_slots.h"

#include <gtest/gtest.h>

#include <optional>

#include "core/util/error.h"

namespace loom::server {
namespace {

const auto kNever = [] { return false; };
const auto kAlready = [] { return true; };

TEST(ParseSlots, ARequestBeyondTheLimitWaitsAndAClientThatLeftIsRefused) {
  ParseSlots slots(2);
  std::optional<ParseSlots::Slot> first(slots.Acquire(kNever));
  std::optional<ParseSlots::Slot> second(slots.Acquire(kNever));
  EXPECT_EQ(slots.in_use(), 2);
  // Both taken: a third would wait; its client has gone, so it is refused.
  try {
    slots.Acquire(kAlready);
    FAIL() << "a third slot was granted";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kUnavailable);
  }
  first.reset();
  EXPECT_EQ(slots.in_use(), 1);
  // A free slot is granted without looking at the client.
  const ParseSlots::Slot third = slots.Acquire(kAlready);
  EXPECT_EQ(slots.in_use(), 2);
}

TEST(ParseSlots, ZeroSlotsIsRefusedNamingTheFlag) {
  try {
    ParseSlots slots(0);
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("--max-concurrent-parses"), std::string::npos);
  }
}

}  // namespace
}  // namespace loom::server
