#include "core/util/parallel_for.h"

#include <gtest/gtest.h>

#include <mutex>
#include <stdexcept>
#include <vector>

namespace loom {
namespace {

// What ParallelRounds called, in the order it called it: 'p' prepare, 'i' an item,
// 'f' finish, each with its round.
struct Event {
  char kind;
  size_t round;
};

class RoundLog {
 public:
  void Add(char kind, size_t round) {
    const std::lock_guard lock(mutex_);
    events_.push_back({kind, round});
  }
  std::vector<Event> events() const { return events_; }

 private:
  mutable std::mutex mutex_;
  std::vector<Event> events_;
};

// Each round is prepare, then `items` items, then finish, the rounds in order.
void ExpectRounds(const std::vector<Event>& events, size_t rounds, size_t items, bool last_finished = true) {
  const size_t per_round = items + 2;
  ASSERT_EQ(events.size(), rounds * per_round - (last_finished ? 0 : 1));
  for (size_t e = 0; e < events.size(); ++e) {
    const size_t round = e / per_round, at = e % per_round;
    EXPECT_EQ(events[e].round, round) << "event " << e;
    EXPECT_EQ(events[e].kind, at == 0 ? 'p' : at == per_round - 1 ? 'f' : 'i') << "event " << e;
  }
}

TEST(ParallelRounds, EachRoundPreparesRunsEveryItemOnceThenFinishes) {
  for (unsigned threads : {1u, 2u, 4u}) {
    RoundLog log;
    std::vector<std::vector<int>> seen(5, std::vector<int>(7, 0));
    ParallelRounds(
        5, 7, threads, [&](size_t round) { log.Add('p', round); },
        [&](size_t round, size_t item, unsigned worker) {
          EXPECT_LT(worker, threads);
          ++seen[round][item];
          log.Add('i', round);
        },
        [&](size_t round) { log.Add('f', round); });
    ExpectRounds(log.events(), 5, 7);
    for (const auto& round : seen) EXPECT_EQ(round, std::vector<int>(7, 1)) << threads << " threads";
  }
}

TEST(ParallelRounds, ThrowingFromAnItemEndsTheLoopBeforeThatRoundFinishes) {
  RoundLog log;
  EXPECT_THROW(ParallelRounds(
                   6, 2, 2, [&](size_t round) { log.Add('p', round); },
                   [&](size_t round, size_t item, unsigned) {
                     log.Add('i', round);
                     if (round == 3 && item == 0) throw std::runtime_error("item");
                   },
                   [&](size_t round) { log.Add('f', round); }),
               std::runtime_error);
  // Rounds 0-2 whole, then round 3's prepare and the items started before the throw.
  std::vector<Event> events = log.events();
  ASSERT_GE(events.size(), 3 * 4 + 2u);
  ASSERT_LE(events.size(), 3 * 4 + 3u);
  for (size_t e = 3 * 4; e < events.size(); ++e) {
    EXPECT_EQ(events[e].round, 3u);
    EXPECT_EQ(events[e].kind, e == 3 * 4 ? 'p' : 'i');
  }
  events.resize(3 * 4);
  ExpectRounds(events, 3, 2);
}

TEST(ParallelRounds, ThrowingFromFinishOrPrepareEndsTheLoop) {
  RoundLog log;
  EXPECT_THROW(ParallelRounds(
                   6, 3, 2, [&](size_t round) { log.Add('p', round); },
                   [&](size_t round, size_t, unsigned) { log.Add('i', round); },
                   [&](size_t round) {
                     log.Add('f', round);
                     if (round == 2) throw std::runtime_error("finish");
                   }),
               std::runtime_error);
  ExpectRounds(log.events(), 3, 3);

  size_t items = 0;
  EXPECT_THROW(ParallelRounds(
                   6, 3, 2, [](size_t round) { if (round == 1) throw std::runtime_error("prepare"); },
                   [&](size_t, size_t, unsigned) { ++items; }, [](size_t) {}),
               std::runtime_error);
  EXPECT_EQ(items, 3u);
}

TEST(ParallelRounds, NoRoundsCallsNothing) {
  int calls = 0;
  ParallelRounds(0, 4, 2, [&](size_t) { ++calls; }, [&](size_t, size_t, unsigned) { ++calls; },
                 [&](size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace loom
